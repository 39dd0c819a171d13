//! Sweep-and-prune: sort the boxes along one axis, sweep, test the other two axes.

use tumble_geometry::{Aabb, Real};

use crate::BroadPhaseError;
use crate::filter::{check_flags, wanted};
use crate::sweep_axis::sweep_axis;

/// A box in sweep order, its coordinates permuted so that the sweep axis comes first:
/// the sweep reads one contiguous 28-byte record per candidate instead of gathering from the
/// caller's slice.
#[derive(Clone, Copy, Debug)]
struct SweptBox {
    /// Lower corner, sweep axis first (12 bytes).
    min: [Real; 3],
    /// Upper corner, sweep axis first (12 bytes).
    max: [Real; 3],
    /// Index of the box in the caller's slice (4 bytes).
    id: u32,
}

/// Sweep-and-prune with reusable scratch buffers, so that a world calling it every step
/// allocates nothing once the buffers have grown to the scene's size.
#[derive(Clone, Debug, Default)]
pub struct SweepAndPrune {
    /// Sort keys: lower bound along the sweep axis, then box index.
    keys: Vec<(Real, u32)>,
    /// The boxes in sweep order.
    swept: Vec<SweptBox>,
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
    /// (one flag per box).
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
        let (o1, o2) = ((axis + 1) % 3, (axis + 2) % 3);

        self.keys.clear();
        self.keys.extend(
            aabbs
                .iter()
                .enumerate()
                .map(|(i, b)| (b.min[axis], i as u32)),
        );
        // Sort by lower bound, ties by index: the order (and so the pair list before its final
        // sort) is the same on every run and on the GPU's sort. `total_cmp` gives NaN a place
        // (at the ends) instead of breaking the sort; a NaN box intersects nothing anyway.
        self.keys
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));

        self.swept.clear();
        self.swept.extend(self.keys.iter().map(|&(_, id)| {
            let b = &aabbs[id as usize];
            SweptBox {
                min: [b.min[axis], b.min[o1], b.min[o2]],
                max: [b.max[axis], b.max[o1], b.max[o2]],
                id,
            }
        }));

        for (i, a) in self.swept.iter().enumerate() {
            for b in &self.swept[i + 1..] {
                // Later boxes start no earlier along the axis, so once one starts past `a`'s
                // end, all do. Written as `!(<=)` so that a NaN bound also ends the window.
                #[allow(clippy::neg_cmp_op_on_partial_ord)]
                if !(b.min[0] <= a.max[0]) {
                    break;
                }
                // The full closed-interval test, as `Aabb::intersects`; the sweep-axis half
                // `a.min <= b.max` matters only for inverted (min > max) boxes.
                let overlap = a.min[0] <= b.max[0]
                    && b.min[1] <= a.max[1]
                    && a.min[1] <= b.max[1]
                    && b.min[2] <= a.max[2]
                    && a.min[2] <= b.max[2];
                if !overlap {
                    continue;
                }
                let pair = (a.id.min(b.id), a.id.max(b.id));
                if is_static.is_none_or(|s| wanted(s, pair.0, pair.1)) {
                    out.push(pair);
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
    let mut out = Vec::new();
    SweepAndPrune::new().find_pairs_filtered(aabbs, is_static, &mut out)?;
    Ok(out)
}
