//! Which candidate pairs the caller wants.

use tumble_geometry::Aabb;

use crate::BroadPhaseError;

/// Errs unless there is one static flag per box.
pub(crate) fn check_flags(aabbs: &[Aabb], is_static: &[bool]) -> Result<(), BroadPhaseError> {
    if aabbs.len() == is_static.len() {
        Ok(())
    } else {
        Err(BroadPhaseError::FlagCountMismatch {
            boxes: aabbs.len(),
            flags: is_static.len(),
        })
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
}
