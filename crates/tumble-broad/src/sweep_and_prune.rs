//! Sweep-and-prune: sort the boxes along one axis, sweep, test the other two axes. The GPU
//! backend's algorithm; on the CPU the step uses the grid (`grid.rs`), and this sweep stays as
//! the GPU's twin and a second reference (it visits about n^(2/3) boxes per box in a pile).

use tumble_geometry::{Aabb, Real};

use crate::filter::{check_flags, wanted};
use crate::sweep_axis::sweep_axis;
use crate::{BroadPhaseError, collect_pairs};

/// The boxes in sweep order, stored as one array per bound (structure of arrays) with the
/// sweep axis first: the inner loop streams through five contiguous `f32` arrays, which the
/// compiler vectorizes, instead of striding over whole boxes.
#[derive(Clone, Debug, Default)]
struct SweptBoxes {
    /// Lower bounds, `min[0]` along the sweep axis (sorted ascending), then the other two.
    min: [Vec<Real>; 3],
    /// Upper bounds, in the same order.
    max: [Vec<Real>; 3],
    /// Index of each box in the caller's slice.
    id: Vec<u32>,
}

impl SweptBoxes {
    fn clear(&mut self) {
        self.min
            .iter_mut()
            .chain(self.max.iter_mut())
            .for_each(Vec::clear);
        self.id.clear();
    }

    fn push(&mut self, b: &Aabb, axes: [usize; 3], id: u32) {
        for (k, &axis) in axes.iter().enumerate() {
            self.min[k].push(b.min[axis]);
            self.max[k].push(b.max[axis]);
        }
        self.id.push(id);
    }
}

/// Sweep-and-prune with reusable scratch buffers, so that a world calling it every step
/// allocates nothing once the buffers have grown to the scene's size.
#[derive(Clone, Debug, Default)]
pub struct SweepAndPrune {
    /// Sort keys: lower bound along the sweep axis, then box index.
    keys: Vec<(Real, u32)>,
    /// The boxes in sweep order.
    swept: SweptBoxes,
    /// The axis the last query swept along.
    axis: usize,
}

impl SweepAndPrune {
    /// An empty broad phase; its buffers grow on first use.
    pub fn new() -> Self {
        Self::default()
    }

    /// The axis (0 = x, 1 = y, 2 = z) the last query swept along.
    pub fn last_axis(&self) -> usize {
        self.axis
    }

    /// Writes every overlapping pair `(i, j)`, `i < j`, sorted ascending, into `out`
    /// (cleared first). Closed intervals, as `Aabb::intersects`: touching boxes form a pair.
    pub fn find_pairs(&mut self, aabbs: &[Aabb], out: &mut Vec<(u32, u32)>) {
        self.sweep(aabbs, None, out);
    }

    /// As `find_pairs`, leaving out pairs whose two boxes are both flagged in `is_static`
    /// (one flag per box; flag every body contacts cannot move, fixed and kinematic alike).
    pub fn find_pairs_filtered(
        &mut self,
        aabbs: &[Aabb],
        is_static: &[bool],
        out: &mut Vec<(u32, u32)>,
    ) -> Result<(), BroadPhaseError> {
        check_flags(aabbs, is_static)?;
        self.sweep(aabbs, Some(is_static), out);
        Ok(())
    }

    fn sweep(&mut self, aabbs: &[Aabb], is_static: Option<&[bool]>, out: &mut Vec<(u32, u32)>) {
        out.clear();
        let axis = sweep_axis(aabbs);
        self.axis = axis;
        let axes = [axis, (axis + 1) % 3, (axis + 2) % 3];

        self.keys.clear();
        self.keys.extend(
            aabbs
                .iter()
                .enumerate()
                .map(|(i, b)| (b.min[axis], i as u32)),
        );
        // Sort by lower bound, ties by index: the order (and so the pair list before its final
        // sort) is the same on every run and on the GPU's sort. `total_cmp` gives NaN a place
        // (negative NaN first, positive NaN last) instead of breaking the sort.
        self.keys
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));

        let s = &mut self.swept;
        s.clear();
        for &(_, id) in &self.keys {
            s.push(&aabbs[id as usize], axes, id);
        }

        let [min0, min1, min2] = &s.min;
        let [max0, max1, max2] = &s.max;
        for i in 0..s.id.len() {
            if min0[i].is_nan() {
                // `a.min <= b.max` fails for every `b`: this box intersects nothing.
                continue;
            }
            let (lo0, hi0) = (min0[i], max0[i]);
            let (lo1, hi1, lo2, hi2) = (min1[i], max1[i], min2[i], max2[i]);
            // Later boxes start no earlier along the axis, so those starting at or before this
            // box's end form a contiguous window (NaN starts sit past it, at the very end).
            let first = i + 1;
            let end = first + min0[first..].partition_point(|&m| m <= hi0);
            let window = first..end;
            let candidates = max0[window.clone()]
                .iter()
                .zip(&min1[window.clone()])
                .zip(&max1[window.clone()])
                .zip(&min2[window.clone()])
                .zip(&max2[window.clone()])
                .zip(&s.id[window]);
            for (((((&b_hi0, &b_lo1), &b_hi1), &b_lo2), &b_hi2), &b_id) in candidates {
                // The rest of the closed-interval test, as `Aabb::intersects`; the sweep-axis
                // half `a.min <= b.max` matters only for inverted (min > max) boxes. Non-short-
                // circuit `&` keeps the loop branch-free but for the rare hit.
                let hit = (lo0 <= b_hi0)
                    & (b_lo1 <= hi1)
                    & (lo1 <= b_hi1)
                    & (b_lo2 <= hi2)
                    & (lo2 <= b_hi2);
                if hit {
                    let a_id = s.id[i];
                    let pair = (a_id.min(b_id), a_id.max(b_id));
                    if is_static.is_none_or(|f| wanted(f, pair.0, pair.1)) {
                        out.push(pair);
                    }
                }
            }
        }
        // Pairs are unique, so the unstable sort is deterministic.
        out.sort_unstable();
    }
}

/// Every overlapping pair `(i, j)`, `i < j`, sorted ascending, by sweep-and-prune along the
/// axis of largest spread. Exactly touching boxes form a pair (closed intervals, as
/// `Aabb::intersects`); the result equals `brute_force_pairs`.
pub fn sweep_and_prune(aabbs: &[Aabb]) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    SweepAndPrune::new().find_pairs(aabbs, &mut out);
    out
}

/// As `sweep_and_prune`, leaving out pairs whose two boxes are both flagged in `is_static`.
pub fn sweep_and_prune_filtered(
    aabbs: &[Aabb],
    is_static: &[bool],
) -> Result<Vec<(u32, u32)>, BroadPhaseError> {
    collect_pairs(|out| SweepAndPrune::new().find_pairs_filtered(aabbs, is_static, out))
}
