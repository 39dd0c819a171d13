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

use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;
use tumble_geometry::{Aabb, Real};

use crate::BroadPhaseError;
use crate::filter::{CollisionGroups, check_flags, check_groups};
use crate::grid::BroadPhase;

mod repair;

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

    /// Whether the kept list answers this call (same boxes count, flags and groups, every box
    /// inside its fat box), can be repaired (the same, but at most [`REPAIR_MAX`] boxes left
    /// their fat boxes: those are in `movers`), or a search must run.
    fn kept(
        &mut self,
        aabbs: &[Aabb],
        is_static: &[bool],
        groups: Option<&[CollisionGroups]>,
    ) -> Kept {
        let same = self.valid
            && self.fat.len() == aabbs.len()
            && self.is_static.as_slice() == is_static
            && self.groups.as_slice() == groups.unwrap_or(&[]);
        if !same || !self.find_movers(aabbs) {
            Kept::Search
        } else if self.movers.is_empty() {
            Kept::Reuse
        } else {
            Kept::Repair
        }
    }

    /// Fills `movers` with the boxes outside their fat boxes, ascending; false (and `movers`
    /// incomplete) when there are more than [`REPAIR_MAX`]. The scan stops soon after the
    /// limit is passed, so a scene in motion pays little for it.
    fn find_movers(&mut self, aabbs: &[Aabb]) -> bool {
        self.movers.clear();
        if aabbs.len() >= PARALLEL_MIN && rayon::current_num_threads() > 1 {
            // Each chunk lists its own movers; a shared count stops every chunk once the
            // limit is passed. The count passes the limit exactly when more than REPAIR_MAX
            // boxes are outside, and otherwise every chunk ran to its end: the list is then
            // complete and, chunk after chunk, ascending.
            let count = AtomicUsize::new(0);
            let chunk = PARALLEL_MIN / 4;
            let found: Vec<Vec<u32>> = aabbs
                .par_chunks(chunk)
                .zip(self.fat.par_chunks(chunk))
                .enumerate()
                .map(|(c, (boxes, fat))| {
                    let mut movers = Vec::new();
                    for (k, (a, f)) in boxes.iter().zip(fat).enumerate() {
                        if !inside(a, f) {
                            if count.fetch_add(1, Ordering::Relaxed) >= REPAIR_MAX {
                                break;
                            }
                            movers.push((c * chunk + k) as u32);
                        }
                    }
                    movers
                })
                .collect();
            if count.load(Ordering::Relaxed) > REPAIR_MAX {
                return false;
            }
            self.movers.extend(found.into_iter().flatten());
        } else {
            for (i, (a, f)) in aabbs.iter().zip(&self.fat).enumerate() {
                if !inside(a, f) {
                    if self.movers.len() == REPAIR_MAX {
                        self.movers.clear();
                        return false;
                    }
                    self.movers.push(i as u32);
                }
            }
        }
        true
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

/// `a` lies inside `f` (closed; false when a bound of either is NaN).
#[inline]
pub(crate) fn inside(a: &Aabb, f: &Aabb) -> bool {
    (0..3).all(|k| f.min[k] <= a.min[k] && a.max[k] <= f.max[k])
}

/// The box grown on every side by [`FAT_FRACTION`] of its smallest side. A box with a NaN or
/// infinite side keeps its bounds (an infinite box contains anything it becomes; a NaN one is
/// never inside anything), as do a flat and an inverted one (no positive side to take a
/// fraction of; either only makes the search run more often).
pub(crate) fn fat_box(a: &Aabb) -> Aabb {
    let side = (0..3)
        .map(|k| a.max[k] - a.min[k])
        .fold(Real::INFINITY, Real::min);
    let margin = FAT_FRACTION * side;
    if !(margin.is_finite() && margin > 0.0) {
        return *a;
    }
    let mut f = *a;
    for k in 0..3 {
        f.min[k] -= margin;
        f.max[k] += margin;
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brute_force_pairs_filtered;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use tumble_geometry::Point3;

    fn random_box(rng: &mut ChaCha8Rng, extent: Real) -> Aabb {
        let c = Point3::new(
            rng.random_range(0.0..extent),
            rng.random_range(0.0..extent),
            rng.random_range(0.0..extent),
        );
        let h = rng.random_range(0.05..0.5);
        Aabb::new(
            c - tumble_geometry::Vec3::repeat(h),
            c + tumble_geometry::Vec3::repeat(h),
        )
    }

    /// The exact pairs with groups, by brute force.
    fn exact(
        aabbs: &[Aabb],
        is_static: &[bool],
        groups: Option<&[CollisionGroups]>,
    ) -> Vec<(u32, u32)> {
        brute_force_pairs_filtered(aabbs, is_static)
            .unwrap()
            .into_iter()
            .filter(|&(i, j)| groups.is_none_or(|g| g[i as usize].interacts_with(g[j as usize])))
            .collect()
    }

    /// A random walk of boxes, most steps moving every box by a little (kept list reused),
    /// some by a lot (searched again), with flags, groups, counts and NaN boxes changing on
    /// some steps: every call's pairs equal brute force's, and both branches are taken. A
    /// kept list that were not filtered by the exact boxes, or that were reused after a box
    /// left its fat box or after the flags changed, fails here.
    #[test]
    fn kept_pairs_equal_brute_force_through_a_random_walk() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut kept = KeptPairs::new();
        let mut aabbs: Vec<Aabb> = (0..300).map(|_| random_box(&mut rng, 8.0)).collect();
        let mut is_static: Vec<bool> = (0..aabbs.len()).map(|_| rng.random_bool(0.1)).collect();
        let mut groups: Vec<CollisionGroups> = vec![CollisionGroups::ALL; aabbs.len()];
        let mut out = Vec::new();
        let mut last_reuse = 0;
        for step in 0..200 {
            // Small moves: a millimetre, well inside a fat margin of at least 1 cm; jumps of up
            // to half a metre on some steps, and on every step of 100..120 (a scene in
            // motion: searches on the exact boxes, a retry on fat boxes every RETRY_EVERY).
            let jump = step % 17 == 5 || (100..120).contains(&step);
            for a in aabbs.iter_mut() {
                let d = if jump { 0.5 } else { 0.001 };
                let v = tumble_geometry::Vec3::new(
                    rng.random_range(-d..d),
                    rng.random_range(-d..d),
                    rng.random_range(-d..d),
                );
                a.min += v;
                a.max += v;
            }
            if step % 23 == 7 {
                let k = rng.random_range(0..aabbs.len());
                is_static[k] = !is_static[k];
            }
            if step % 29 == 11 {
                aabbs.push(random_box(&mut rng, 8.0));
                is_static.push(false);
                groups.push(CollisionGroups::ALL);
            }
            if step % 31 == 13 {
                let k = rng.random_range(0..aabbs.len());
                groups[k] = CollisionGroups::new(0b10, 0b10);
            }
            let nan_step = step % 37 == 19;
            let saved = aabbs[0];
            if nan_step {
                aabbs[0].min.x = Real::NAN;
            }
            let grouped = (step / 50) % 2 == 1;
            let g = grouped.then_some(groups.as_slice());
            kept.find_pairs(&aabbs, &is_static, g, &mut out).unwrap();
            assert_eq!(out, exact(&aabbs, &is_static, g), "step {step}");
            if nan_step {
                assert!(
                    !kept.reused_last() || kept.repaired_last(),
                    "a NaN box is never inside its fat box"
                );
                aabbs[0] = saved;
            }
            if (101..120).contains(&step) {
                assert!(!kept.reused_last(), "step {step}: every box jumped");
            }
            if kept.reused_last() {
                last_reuse = step;
            }
            // Within RETRY_EVERY calls of a search on the exact boxes comes one on fat boxes,
            // and the list is reused after it; the flag change of step 122 and the jump of
            // step 124 each drop a list, so allow two such waits.
            if step == 120 + 2 * RETRY_EVERY as usize + 1 {
                assert!(last_reuse > 120, "at rest again, reused by step {step}");
            }
        }
        let (searches, reuses) = kept.counts();
        assert!(
            searches >= 20 && reuses >= 50,
            "searches {searches}, reuses {reuses}"
        );
    }

    /// At rest the list is reused; a box moved out of its fat box has its pairs found again
    /// alone (the list repaired), and more than [`REPAIR_MAX`] such boxes make it search again.
    #[test]
    fn a_box_leaving_its_fat_box_is_repaired_and_many_make_it_search_again() {
        let n = 40;
        let boxes: Vec<Aabb> = (0..n)
            .map(|i| {
                let x = i as Real * 1.0;
                Aabb::new(Point3::new(x, 0.0, 0.0), Point3::new(x + 1.0, 1.0, 1.0))
            })
            .collect();
        let flags = vec![false; boxes.len()];
        let mut kept = KeptPairs::new();
        let mut out = Vec::new();
        kept.find_pairs(&boxes, &flags, None, &mut out).unwrap();
        assert!(!kept.reused_last());
        kept.find_pairs(&boxes, &flags, None, &mut out).unwrap();
        assert!(kept.reused_last() && !kept.repaired_last());
        assert_eq!(out.len(), n - 1, "touching neighbours pair: {out:?}");
        // 9 cm is inside the 10 cm fat margin of a 1 m box; 11 cm is not.
        let mut moved = boxes.clone();
        moved[4].min.y += 0.09;
        moved[4].max.y += 0.09;
        kept.find_pairs(&moved, &flags, None, &mut out).unwrap();
        assert!(kept.reused_last() && !kept.repaired_last());
        moved[4].min.y += 0.02;
        moved[4].max.y += 0.02;
        kept.find_pairs(&moved, &flags, None, &mut out).unwrap();
        assert!(kept.reused_last() && kept.repaired_last());
        assert_eq!(out, brute_force_pairs_filtered(&moved, &flags).unwrap());
        // Box 4 lifted clear of its neighbours (1.2 m up), box 30 put on top of box 10: their
        // old pairs go, the new one comes.
        for (k, dx, dy) in [(4, 0.0, 1.09), (30, -20.0, 1.0)] {
            moved[k].min.x += dx;
            moved[k].max.x += dx;
            moved[k].min.y += dy;
            moved[k].max.y += dy;
        }
        kept.find_pairs(&moved, &flags, None, &mut out).unwrap();
        assert!(kept.repaired_last());
        let expected = brute_force_pairs_filtered(&moved, &flags).unwrap();
        assert!(expected.contains(&(10, 30)) && !expected.contains(&(3, 4)));
        assert_eq!(out, expected);
        // REPAIR_MAX boxes out of their fat boxes: still repaired; one more: the search runs
        // again.
        for b in moved.iter_mut().skip(20).take(REPAIR_MAX) {
            b.min.z += 0.5;
            b.max.z += 0.5;
        }
        kept.find_pairs(&moved, &flags, None, &mut out).unwrap();
        assert!(kept.repaired_last());
        assert_eq!(out, brute_force_pairs_filtered(&moved, &flags).unwrap());
        for b in moved.iter_mut().skip(20).take(REPAIR_MAX + 1) {
            b.min.z += 0.5;
            b.max.z += 0.5;
        }
        kept.find_pairs(&moved, &flags, None, &mut out).unwrap();
        assert!(!kept.reused_last() && !kept.repaired_last());
        assert_eq!(out, brute_force_pairs_filtered(&moved, &flags).unwrap());
        assert_eq!(kept.repairs(), 3);
    }

    /// A kept list past [`PARALLEL_MIN`] pairs, reused on pools of one and four threads: the
    /// filter and the containment check then run on the pool, and the pairs must still be
    /// brute force's, in its order, with some kept pairs filtered out (so the filter's order
    /// is tested, not only its count). A filter that lost rayon's order, or kept a pair whose
    /// exact boxes part, fails here.
    #[test]
    fn a_large_kept_list_is_filtered_on_the_pool_in_order() {
        // 28 x 28 x 28 cubes of 1 m, 5 cm apart: each touches none of its neighbours, but every
        // fat box (grown 10 cm) overlaps its 26 neighbours' fat boxes, so the kept list holds
        // 264,708 pairs and the exact filter keeps those moved into contact below.
        let n = 28;
        let mut boxes = Vec::new();
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let p = Point3::new(i as Real * 1.05, j as Real * 1.05, k as Real * 1.05);
                    boxes.push(Aabb::new(p, p + tumble_geometry::Vec3::repeat(1.0)));
                }
            }
        }
        let flags = vec![false; boxes.len()];
        // Every seventh box grown by 6 cm along x (inside its fat box): it touches its +x
        // neighbour.
        let mut moved = boxes.clone();
        for b in moved.iter_mut().step_by(7) {
            b.max.x += 0.06;
        }
        let expected = brute_force_pairs_filtered(&moved, &flags).unwrap();
        assert!(!expected.is_empty());
        for threads in [1, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut kept = KeptPairs::new();
            let mut out = Vec::new();
            pool.install(|| kept.find_pairs(&boxes, &flags, None, &mut out))
                .unwrap();
            assert!(out.is_empty(), "the cubes stand apart: {} pairs", out.len());
            assert!(
                kept.pairs.len() > PARALLEL_MIN,
                "{} kept pairs",
                kept.pairs.len()
            );
            pool.install(|| kept.find_pairs(&moved, &flags, None, &mut out))
                .unwrap();
            assert!(kept.reused_last(), "{threads} threads");
            assert_eq!(out, expected, "{threads} threads");
            // Five boxes, in different chunks of the containment check, moved 2.25 m up (out
            // of their fat boxes, into the boxes two and three rows up, which were not in
            // their kept pairs): the check, on the pool too, must find them all, and the
            // repair their new pairs.
            let mut out_of_fat = moved.clone();
            let last = out_of_fat.len() - 1;
            for k in [0, 5_000, 10_000, 15_000, last] {
                out_of_fat[k].min.y += 2.25;
                out_of_fat[k].max.y += 2.25;
            }
            let before = out.clone();
            pool.install(|| kept.find_pairs(&out_of_fat, &flags, None, &mut out))
                .unwrap();
            assert!(kept.repaired_last(), "{threads} threads");
            let expected = brute_force_pairs_filtered(&out_of_fat, &flags).unwrap();
            assert_ne!(expected, before, "the moved boxes touch new neighbours");
            assert_eq!(out, expected, "{threads} threads");
            // REPAIR_MAX boxes, one per 1,300 (in every chunk of the check), moved 2.25 m
            // down: repaired; from the same kept list, one more: the search runs.
            let moved_down = |count: usize| {
                let mut boxes = out_of_fat.clone();
                for b in boxes.iter_mut().step_by(1_300).take(count) {
                    b.min.y -= 2.25;
                    b.max.y -= 2.25;
                }
                boxes
            };
            let mut one_more = kept.clone();
            let limit = moved_down(REPAIR_MAX);
            pool.install(|| kept.find_pairs(&limit, &flags, None, &mut out))
                .unwrap();
            assert!(kept.repaired_last(), "{threads} threads");
            assert_eq!(out, brute_force_pairs_filtered(&limit, &flags).unwrap());
            let past = moved_down(REPAIR_MAX + 1);
            pool.install(|| one_more.find_pairs(&past, &flags, None, &mut out))
                .unwrap();
            assert!(!one_more.reused_last(), "{threads} threads");
            assert_eq!(out, brute_force_pairs_filtered(&past, &flags).unwrap());
            // And every box moved: more than REPAIR_MAX, so the search runs.
            let shifted: Vec<Aabb> = out_of_fat
                .iter()
                .map(|b| {
                    let d = tumble_geometry::Vec3::new(0.0, 0.2, 0.0);
                    Aabb::new(b.min + d, b.max + d)
                })
                .collect();
            pool.install(|| kept.find_pairs(&shifted, &flags, None, &mut out))
                .unwrap();
            assert!(!kept.reused_last(), "{threads} threads");
            assert_eq!(
                out,
                brute_force_pairs_filtered(&shifted, &flags).unwrap(),
                "{threads} threads"
            );
        }
    }
}
