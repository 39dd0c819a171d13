//! Pairs kept from step to step: the grid searched on enlarged boxes only when more than a few
//! boxes left their enlarged boxes (fewer are repaired alone), the pair list filtered by the
//! exact boxes every call.
//!
//! A resting pile moves by micrometres per step, yet the grid search of `grid.rs` finds its
//! pairs anew every step (3 to 8 ms for the 42,926 boxes of the resting pyramid of 50 on one
//! thread of the 2-core build machine; docs/benchmarks.md). Box2D v3 keeps an enlarged
//! ("fat") AABB per proxy in its dynamic tree, grown by `B2_AABB_MARGIN` (0.1 m), and
//! re-inserts a proxy only when its tight box leaves the fat one; rapier's BVH broad phase
//! refits a kept tree and skips unchanged pairs. This is the same idea on the grid, kept
//! exact:
//!
//! - The grid search runs on the boxes grown by [`FAT_FRACTION`] of their smallest side (the
//!   "fat" boxes), and its pair list is kept with the fat boxes and the filter it ran under.
//! - On the next call, if every box still lies inside its fat box (and the box count, the
//!   static flags and the collision groups are unchanged), the kept list is reused; if at
//!   most [`REPAIR_MAX`] boxes left theirs, it is repaired (below); otherwise the search runs
//!   again on new fat boxes.
//! - Either way the kept list is filtered by the exact boxes: a pair is written out when its
//!   two boxes intersect.
//!
//! Why the output is exactly the search's on the exact boxes: growing a box only lowers its
//! `min` and raises its `max`, and `Aabb::intersects` (closed intervals, `a.min <= b.max` and
//! `b.min <= a.max` on each axis) can only turn true under that, so two boxes that intersect
//! have fat boxes that intersect, and their pair is in the kept list (same filter); the
//! exact test then keeps exactly the pairs that intersect. The kept list is sorted, and
//! filtering keeps its order. A box with a NaN bound is never inside its fat box, so in a scene
//! with one the list is repaired (or searched) every call (and such a box pairs with nothing,
//! as in the search). So
//! the pairs, and every step built on them, are the same bits as without keeping.
//!
//! What it saves: the search, when nothing left its fat box. When a few boxes left theirs (at
//! most [`REPAIR_MAX`]: a ball rolling over a resting pile, a few boxes settling), the list is
//! repaired instead of searched again, as Box2D v3 re-inserts only the proxies that left their
//! fat boxes: each such box gets a new fat box, its pairs are dropped from the list, and the
//! pairs of its new fat box with every other fat box are found by one pass over the fat boxes
//! (module `repair`). The other boxes' fat boxes did not change, so the repaired list holds
//! every pair of intersecting fat boxes, as a search on the new fat boxes would, and the exact
//! filter gives the same pairs. More boxes than that make the whole search run again. A search
//! on fat boxes costs more than one on the exact boxes (more pairs, then the filter:
//! about 1.2 to 1.4 times, docs/benchmarks.md), so when a kept list was not reused even once
//! before the next search was needed, the searches that follow run on the exact boxes and
//! keep nothing, and only every [`RETRY_EVERY`]th one tries fat boxes again: a scene where
//! something always moves pays about the plain search plus the containment test, and one that
//! comes to rest is kept again within that many steps.

use rayon::prelude::*;
use tumble_geometry::{Aabb, Real};

use crate::BroadPhaseError;
use crate::filter::{CollisionGroups, check_flags, check_groups};
use crate::grid::BroadPhase;

mod movers;
mod repair;

use movers::fat_box;

/// How much a fat box is grown on every side: this fraction of the exact box's smallest side.
/// A unit cube's box (1.04 m with the step's 2 cm margin) grows by 10 cm, Box2D's
/// `B2_AABB_MARGIN` for its usual object sizes; relative, so tiny and huge boxes get a margin
/// of their own scale, and the smallest side, so that a floor slab 40 m wide does not reach
/// 4 m up into a pile and pair with every box there.
pub const FAT_FRACTION: Real = 0.1;

/// While the kept lists are not being reused, one search in this many runs on fat boxes (to
/// find out whether the scene has come to rest); the others run on the exact boxes.
pub const RETRY_EVERY: u32 = 8;

/// Kept pairs (and boxes) from which the exact-box filter (and the containment check) runs on
/// the rayon pool, when it has more than one thread: below it a task's hand-off costs more
/// than the test of the pairs it would take (a few nanoseconds each).
const PARALLEL_MIN: usize = 16_384;

/// At most this many boxes may leave their fat boxes for the kept list to be repaired (module
/// `repair`) instead of searched again. The repair tests every fat box against the movers'
/// joint bounds and, where that hits, against each mover (a few nanoseconds a test), where the
/// search costs about 50 ns a box (docs/benchmarks.md): with 16 movers spread over the whole
/// scene it stays below the search, and movers close together cost about one test a box.
pub const REPAIR_MAX: usize = 16;

/// What the last call did with the kept list.
enum Kept {
    /// Every box inside its fat box: the list answers as it is.
    Reuse,
    /// At most [`REPAIR_MAX`] boxes left their fat boxes (`KeptPairs::movers`): repair.
    Repair,
    /// No list, or it does not belong to these boxes, or too many left: search.
    Search,
}

/// The grid broad phase with its pair list kept between calls (see the module
/// documentation of `kept.rs`). Its result is exactly [`BroadPhase`]'s on the same input.
#[derive(Clone, Debug, Default)]
pub struct KeptPairs {
    /// The grid search, run on the fat boxes.
    grid: BroadPhase,
    /// The fat boxes of the last search, with the repaired boxes' new ones.
    fat: Vec<Aabb>,
    /// The static flags of the last search.
    is_static: Vec<bool>,
    /// The collision groups of the last search; empty when it had none.
    groups: Vec<CollisionGroups>,
    /// Every pair of intersecting boxes of `fat` that the filter wants, sorted: the last
    /// search's, as repaired since.
    pairs: Vec<(u32, u32)>,
    /// Whether `fat` and `pairs` belong together (false before the first search).
    valid: bool,
    /// Whether the last call reused the kept list (repaired or not).
    reused: bool,
    /// Whether the last call repaired the kept list.
    repaired: bool,
    /// Searches since the last call that reused a kept list.
    misses: u32,
    /// Searches run, calls that reused the list and calls that repaired it, since creation.
    searches: u64,
    reuses: u64,
    repairs: u64,
    /// The boxes that left their fat boxes, ascending (at most `REPAIR_MAX`).
    movers: Vec<u32>,
    /// Per box, whether it is among `movers` (all false between calls).
    moved: Vec<bool>,
    /// The movers' new fat boxes, sorted for the repair's tests.
    mover_boxes: Vec<(Aabb, u32)>,
    /// The movers' new pairs, then the repaired list before it replaces `pairs`.
    fresh: Vec<(u32, u32)>,
    merged: Vec<(u32, u32)>,
}

impl KeptPairs {
    /// Nothing kept yet; the first call searches.
    pub fn new() -> Self {
        Self::default()
    }

    /// Whether the last call answered from the kept pair list (no grid search), as it was or
    /// repaired.
    pub fn reused_last(&self) -> bool {
        self.reused
    }

    /// Whether the last call repaired the kept pair list: some boxes, at most [`REPAIR_MAX`],
    /// had left their fat boxes, and only their pairs were found again.
    pub fn repaired_last(&self) -> bool {
        self.repaired
    }

    /// Grid searches run and calls answered from the kept list (repaired or not), since
    /// creation.
    pub fn counts(&self) -> (u64, u64) {
        (self.searches, self.reuses)
    }

    /// Calls that repaired the kept list, since creation (also counted as reuses).
    pub fn repairs(&self) -> u64 {
        self.repairs
    }

    /// The grid of the last search (its cell size and side list describe the fat boxes that
    /// search ran on; the boxes repaired since are not in it).
    pub fn grid(&self) -> &BroadPhase {
        &self.grid
    }

    /// Forgets the kept list: the next call searches.
    pub fn clear(&mut self) {
        self.valid = false;
    }

    /// As [`BroadPhase::find_pairs_filtered`] (`groups: None`) or
    /// [`BroadPhase::find_pairs_grouped`]: every intersecting pair `(i, j)`, `i < j`, whose
    /// boxes are not both static (and whose groups interact), sorted, into `out` (cleared
    /// first).
    pub fn find_pairs(
        &mut self,
        aabbs: &[Aabb],
        is_static: &[bool],
        groups: Option<&[CollisionGroups]>,
        out: &mut Vec<(u32, u32)>,
    ) -> Result<(), BroadPhaseError> {
        check_flags(aabbs, is_static)?;
        if let Some(groups) = groups {
            check_groups(aabbs, groups)?;
        }
        out.clear();
        let kept = self.kept(aabbs, is_static, groups);
        self.reused = !matches!(kept, Kept::Search);
        self.repaired = matches!(kept, Kept::Repair);
        if self.reused {
            self.reuses += 1;
            self.misses = 0;
            if self.repaired {
                self.repairs += 1;
                self.repair(aabbs, is_static, groups);
            }
        } else {
            self.misses += 1;
            if self.misses > 1 && !self.misses.is_multiple_of(RETRY_EVERY) {
                // Moving: the plain search on the exact boxes, nothing kept.
                self.valid = false;
                self.searches += 1;
                return match groups {
                    Some(groups) => self.grid.find_pairs_grouped(aabbs, is_static, groups, out),
                    None => self.grid.find_pairs_filtered(aabbs, is_static, out),
                };
            }
            self.search(aabbs, is_static, groups)?;
        }
        let touching = |&(i, j): &(u32, u32)| aabbs[i as usize].intersects(&aabbs[j as usize]);
        if self.pairs.len() >= PARALLEL_MIN && rayon::current_num_threads() > 1 {
            // Rayon's extend of a filtered iterator keeps the order: the same list.
            out.par_extend(
                self.pairs
                    .par_iter()
                    .with_min_len(PARALLEL_MIN / 4)
                    .copied()
                    .filter(touching),
            );
        } else {
            out.extend(self.pairs.iter().copied().filter(touching));
        }
        Ok(())
    }

    /// Grows every box into its fat box and runs the grid search on those.
    fn search(
        &mut self,
        aabbs: &[Aabb],
        is_static: &[bool],
        groups: Option<&[CollisionGroups]>,
    ) -> Result<(), BroadPhaseError> {
        self.valid = false;
        self.fat.clear();
        self.fat.extend(aabbs.iter().map(fat_box));
        match groups {
            Some(groups) => {
                self.grid
                    .find_pairs_grouped(&self.fat, is_static, groups, &mut self.pairs)?;
                self.groups.clear();
                self.groups.extend_from_slice(groups);
            }
            None => {
                self.grid
                    .find_pairs_filtered(&self.fat, is_static, &mut self.pairs)?;
                self.groups.clear();
            }
        }
        self.is_static.clear();
        self.is_static.extend_from_slice(is_static);
        self.searches += 1;
        self.valid = true;
        Ok(())
    }
}

#[cfg(test)]
mod tests;
