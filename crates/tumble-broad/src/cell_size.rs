//! The grid's cell size, and which boxes the grid holds.

use tumble_geometry::{Aabb, Real};

/// Boxes longer than this many median box sizes do not set the cell size: they go to the
/// side list (a floor under a pile of unit cubes is a hundred of them).
const OVERSIZE_FACTOR: Real = 4.0;

/// At most this many boxes, evenly spaced through the input, estimate the median size.
const SAMPLE: usize = 1023;

/// Where a box goes in the grid broad phase.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// At most two cells on every axis: stored in the grid.
    Grid,
    /// Larger, inverted or infinite: tested against every box.
    Side,
    /// A NaN bound: intersects nothing.
    Never,
}

/// The size of a box: its longest side; `None` for boxes with a non-finite or inverted side.
#[inline]
fn size(b: &Aabb) -> Option<Real> {
    let d = b.max - b.min;
    let s = d.x.max(d.y).max(d.z);
    (d.x >= 0.0 && d.y >= 0.0 && d.z >= 0.0 && s.is_finite()).then_some(s)
}

/// The cell size for `aabbs`: the largest box size up to `OVERSIZE_FACTOR` times the median
/// (estimated from a deterministic sample), a hair more so that a box of exactly that size
/// spans two cells rather than three; 1 when no box has a positive finite size. Only the
/// speed depends on it: any positive finite size gives the exact pairs.
pub(crate) fn cell_size(aabbs: &[Aabb], sample: &mut Vec<Real>) -> Real {
    sample.clear();
    let step = aabbs.len().div_ceil(SAMPLE).max(1);
    sample.extend(aabbs.iter().step_by(step).filter_map(size));
    if sample.is_empty() {
        return 1.0;
    }
    let mid = sample.len() / 2;
    let (_, &mut median, _) = sample.select_nth_unstable_by(mid, |a, b| a.total_cmp(b));
    let limit = median * OVERSIZE_FACTOR;
    let largest = aabbs
        .iter()
        .filter_map(size)
        .filter(|&s| s <= limit)
        .fold(0.0, Real::max);
    let h = largest * (1.0 + 1.0 / 1024.0);
    if h.is_normal() && (1.0 / h).is_normal() {
        h
    } else {
        1.0
    }
}

/// The grid boxes' lower-corner cells: per box (grid boxes only), their bounds and count.
#[derive(Clone, Debug, Default)]
pub(crate) struct Corners {
    /// Per box, in input order: the cell of its lower corner (grid boxes only).
    pub(crate) cell: Vec<[i32; 3]>,
    /// Per box, in input order: bit `k` set when its upper corner lies one cell above its
    /// lower corner on axis `k` (grid boxes only; on the other axes both lie in one cell).
    pub(crate) span: Vec<u8>,
    /// The lowest and highest of them on each axis.
    pub(crate) lo: [i32; 3],
    pub(crate) hi: [i32; 3],
    /// How many boxes are grid boxes.
    pub(crate) count: usize,
}

/// Sorts each box into grid, side list or never, for the cell function `cell` at
/// `inv = 1 / cell size`: a grid box spans at most two cells on every axis (by the same
/// function the grid uses, so the search's bound holds whatever the rounding). Records the
/// grid boxes' lower-corner cells and spans in `corners`.
pub(crate) fn classify(
    aabbs: &[Aabb],
    inv: Real,
    cell: impl Fn(Real, Real) -> i32,
    kind: &mut Vec<Kind>,
    corners: &mut Corners,
) {
    kind.clear();
    corners.cell.clear();
    corners.cell.resize(aabbs.len(), [0; 3]);
    corners.span.clear();
    corners.span.resize(aabbs.len(), 0);
    let (mut lo, mut hi) = ([i32::MAX; 3], [i32::MIN; 3]);
    let mut count = 0;
    let slots = corners.cell.iter_mut().zip(&mut corners.span);
    kind.extend(aabbs.iter().zip(slots).map(|(b, (corner, span))| {
        let bounds = [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z];
        if bounds.iter().any(|v| v.is_nan()) {
            return Kind::Never;
        }
        if size(b).is_none() {
            return Kind::Side;
        }
        let c: [i32; 3] = std::array::from_fn(|k| cell(b.min[k], inv));
        let d: [i32; 3] = std::array::from_fn(|k| cell(b.max[k], inv) - c[k]);
        if d.iter().any(|&d| d > 1) {
            return Kind::Side;
        }
        // `d` is 0 or 1 (`max >= min` and the cell function is monotone).
        *span = (d[0] | (d[1] << 1) | (d[2] << 2)) as u8;
        for k in 0..3 {
            lo[k] = lo[k].min(c[k]);
            hi[k] = hi[k].max(c[k]);
        }
        *corner = c;
        count += 1;
        Kind::Grid
    }));
    corners.lo = lo;
    corners.hi = hi;
    corners.count = count;
}
