//! Which candidate pairs the caller wants.

use tumble_geometry::Aabb;

use crate::BroadPhaseError;

/// Which bodies a body may collide with: a body belongs to the groups whose bits are set in
/// `memberships` and collides with the groups whose bits are set in `filter`. Two bodies `a`
/// and `b` may collide only when `a.memberships & b.filter != 0` and
/// `b.memberships & a.filter != 0`, so either side can refuse the pair. The default,
/// [`CollisionGroups::ALL`], belongs to every group and collides with every group.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CollisionGroups {
    /// The groups the body belongs to, one bit each.
    pub memberships: u32,
    /// The groups the body collides with, one bit each.
    pub filter: u32,
}

impl CollisionGroups {
    /// Member of every group, colliding with every group: everything collides.
    pub const ALL: Self = Self::new(u32::MAX, u32::MAX);
    /// Member of no group, colliding with none: the body collides with nothing.
    pub const NONE: Self = Self::new(0, 0);

    /// Groups with the given `memberships` and `filter` bits.
    pub const fn new(memberships: u32, filter: u32) -> Self {
        Self {
            memberships,
            filter,
        }
    }

    /// True when a body with these groups and one with `other` may collide (the test is
    /// symmetric).
    pub const fn interacts_with(self, other: Self) -> bool {
        (self.memberships & other.filter) != 0 && (other.memberships & self.filter) != 0
    }
}

impl Default for CollisionGroups {
    fn default() -> Self {
        Self::ALL
    }
}

/// What the pair filter reads per box: the static flags, and the collision groups when any
/// box has groups other than [`CollisionGroups::ALL`] (`None` lets every pair through).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Filter<'a> {
    pub is_static: &'a [bool],
    pub groups: Option<&'a [CollisionGroups]>,
}

impl Filter<'_> {
    /// [`wanted`], then the groups.
    #[inline]
    pub fn wants(&self, i: u32, j: u32) -> bool {
        wanted(self.is_static, i, j)
            && self
                .groups
                .is_none_or(|g| g[i as usize].interacts_with(g[j as usize]))
    }

    /// True when some pair of box `i` may be left out: `i` is static, or groups apply.
    #[inline]
    pub fn may_drop(&self, i: u32) -> bool {
        self.is_static[i as usize] || self.groups.is_some()
    }
}

/// Errs unless there is one collision-groups entry per box.
pub(crate) fn check_groups(
    aabbs: &[Aabb],
    groups: &[CollisionGroups],
) -> Result<(), BroadPhaseError> {
    check_count(aabbs.len(), groups.len(), |boxes, groups| {
        BroadPhaseError::GroupCountMismatch { boxes, groups }
    })
}

/// Errs unless there is one static flag per box.
pub(crate) fn check_flags(aabbs: &[Aabb], is_static: &[bool]) -> Result<(), BroadPhaseError> {
    check_count(aabbs.len(), is_static.len(), |boxes, flags| {
        BroadPhaseError::FlagCountMismatch { boxes, flags }
    })
}

/// Errs with `mismatch(boxes, entries)` unless a per-box slice has one entry per box.
fn check_count(
    boxes: usize,
    entries: usize,
    mismatch: impl FnOnce(usize, usize) -> BroadPhaseError,
) -> Result<(), BroadPhaseError> {
    if boxes == entries {
        Ok(())
    } else {
        Err(mismatch(boxes, entries))
    }
}

/// A pair is wanted unless both boxes are static. "Static" means contacts cannot move the
/// body (fixed and kinematic bodies): two such bodies need no contact, however much they
/// overlap (a floor meeting a wall, a kinematic platform passing through the floor).
///
/// The filter of [`crate::SweepAndPrune::find_pairs_filtered`], public so that a pair list
/// found elsewhere (on the GPU, or before some bodies became immovable) is filtered by the
/// same rule.
#[inline]
pub fn wanted(is_static: &[bool], i: u32, j: u32) -> bool {
    !(is_static[i as usize] && is_static[j as usize])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_pairs_of_two_immovable_bodies_are_dropped() {
        // 0 fixed floor, 1 kinematic platform, 2 and 3 dynamic.
        let immovable = [true, true, false, false];
        assert!(!wanted(&immovable, 0, 1));
        assert!(wanted(&immovable, 0, 2));
        assert!(wanted(&immovable, 1, 3));
        assert!(wanted(&immovable, 2, 3));
        let kept: Vec<(u32, u32)> = [(0, 1), (0, 2), (1, 2), (2, 3)]
            .into_iter()
            .filter(|&(i, j)| wanted(&immovable, i, j))
            .collect();
        assert_eq!(kept, vec![(0, 2), (1, 2), (2, 3)]);
    }

    #[test]
    fn groups_refuse_a_pair_from_either_side() {
        let player = CollisionGroups::new(0b01, 0b10);
        let enemy = CollisionGroups::new(0b10, 0b01);
        let ghost = CollisionGroups::new(0b01, 0b00);
        assert!(player.interacts_with(enemy) && enemy.interacts_with(player));
        // Player with player: each is a member of 0b01, but filters only 0b10.
        assert!(!player.interacts_with(player));
        // The ghost belongs to the player's group, which enemies collide with, but its own
        // filter is empty: the pair is refused from the ghost's side only.
        assert!(!ghost.interacts_with(enemy) && !enemy.interacts_with(ghost));
        assert!(CollisionGroups::ALL.interacts_with(CollisionGroups::ALL));
        assert!(!CollisionGroups::NONE.interacts_with(CollisionGroups::ALL));
        assert_eq!(CollisionGroups::default(), CollisionGroups::ALL);
        let groups = [player, enemy, player];
        let filter = Filter {
            is_static: &[false; 3],
            groups: Some(&groups),
        };
        assert!(filter.wants(0, 1) && !filter.wants(0, 2));
    }
}
