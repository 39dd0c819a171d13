//! The broad phase of the step: a hashed uniform grid, queried box by box in index order, so
//! that the pairs come out sorted without sorting them.
//!
//! Each box whose AABB spans at most two cells on every axis ("grid box") is stored once, in
//! the cell of its lower corner. A grid box `j` that overlaps box `i` then has its lower
//! corner's cell within `[lo_i - 1, hi_i]` on every axis (`lo`, `hi`: the cells of `i`'s
//! corners), at most 3 x 3 x 3 cells. The cell of a coordinate is `floor(x / h)`, a
//! monotone function of `x`, so overlapping intervals have overlapping cell ranges whatever
//! the rounding: the search is exact, only its speed depends on the cell size `h`.
//!
//! The few boxes that span more cells (a floor under a pile, a long plank), inverted boxes
//! (`min > max` on some axis) and infinite ones go to a side list and are tested against
//! every box. Boxes with a NaN bound intersect nothing (`Aabb::intersects` compares false)
//! and are left out.
//!
//! Cells are hashed into a power-of-two bucket table, a row of cells along x onto
//! consecutive buckets, so the three cells of a query row are one contiguous run of the
//! bucket-sorted boxes. Unrelated cells sharing a bucket only add candidates, which the exact
//! AABB test rejects; a bucket reached twice by one query (two rows hashed onto it) is
//! removed by the per-box dedup.

use tumble_geometry::{Aabb, Real};

use crate::BroadPhaseError;
use crate::cell_size::{Kind, cell_size, classify};
use crate::filter::{check_flags, wanted};

/// Cell coordinates are clamped to `±CELL_LIMIT`, so that `lo - 1` cannot overflow; the
/// clamp is monotone, which is all the search needs.
const CELL_LIMIT: i32 = 1 << 30;

/// The cell of coordinate `x` for `inv = 1 / h`: `floor(x / h)`, clamped. Monotone in `x`.
#[inline]
fn cell(x: Real, inv: Real) -> i32 {
    // `as` saturates (and maps the infinities to the limits), both monotone.
    ((x * inv).floor() as i32).clamp(-CELL_LIMIT, CELL_LIMIT)
}

/// The bucket hash of the row of cells `(cy, cz)`; cell `cx` of that row goes to bucket
/// `row_hash + cx` (modulo the table size), so a row's neighbouring cells are neighbouring
/// buckets.
#[inline]
fn row_hash(cy: i32, cz: i32) -> u32 {
    let mut h = (cy as u32).wrapping_mul(0x9E37_79B1) ^ (cz as u32).wrapping_mul(0x85EB_CA77);
    h ^= h >> 15;
    h = h.wrapping_mul(0x2C1B_3C6D);
    h ^ (h >> 12)
}

/// The grid boxes sorted by bucket, one array per bound (structure of arrays).
#[derive(Clone, Debug, Default)]
struct Buckets {
    /// `start[b]..start[b + 1]`: the boxes of bucket `b`, in the arrays below.
    start: Vec<u32>,
    min: [Vec<Real>; 3],
    max: [Vec<Real>; 3],
    id: Vec<u32>,
}

/// The broad phase the step uses: a hashed uniform grid with a side list for oversized
/// boxes (see the module documentation of `grid.rs`), with reusable buffers, so that a
/// world calling it every step allocates nothing once they have grown to the scene's size.
///
/// Its result is exactly [`crate::brute_force_pairs`]'s: every overlapping pair `(i, j)`,
/// `i < j`, once, sorted ascending, closed intervals (touching boxes form a pair).
#[derive(Clone, Debug, Default)]
pub struct BroadPhase {
    /// Per box, in input order: grid, side list, or never pairs.
    kind: Vec<Kind>,
    /// Per box, in input order: its bucket (grid boxes only).
    bucket: Vec<u32>,
    /// The grid boxes by bucket.
    grid: Buckets,
    /// Indices of the side-list boxes, ascending.
    side: Vec<u32>,
    /// Every pair with a side-list box in it, sorted.
    side_pairs: Vec<(u32, u32)>,
    /// The partners `j > i` of the box `i` being queried.
    partners: Vec<u32>,
    /// Scratch for the cell-size choice.
    sample: Vec<Real>,
    /// The cell size of the last query.
    cell: Real,
}

impl BroadPhase {
    /// An empty broad phase; its buffers grow on first use.
    pub fn new() -> Self {
        Self::default()
    }

    /// The cell size the last query used (0 before the first, or when it had no grid box).
    pub fn cell_size(&self) -> Real {
        self.cell
    }

    /// How many boxes of the last query went to the side list (tested against every box).
    pub fn oversized(&self) -> usize {
        self.side.len()
    }

    /// Writes every overlapping pair `(i, j)`, `i < j`, sorted ascending, into `out`
    /// (cleared first). Closed intervals, as `Aabb::intersects`: touching boxes form a pair.
    pub fn find_pairs(&mut self, aabbs: &[Aabb], out: &mut Vec<(u32, u32)>) {
        self.run(aabbs, None, out);
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
        self.run(aabbs, Some(is_static), out);
        Ok(())
    }

    fn run(&mut self, aabbs: &[Aabb], is_static: Option<&[bool]>, out: &mut Vec<(u32, u32)>) {
        out.clear();
        assert!(
            aabbs.len() <= u32::MAX as usize,
            "box indices must fit in u32"
        );
        let h = cell_size(aabbs, &mut self.sample);
        self.cell = h;
        let inv = 1.0 / h;
        classify(aabbs, inv, cell, &mut self.kind);
        self.build_grid(aabbs, inv);
        self.pair_side_boxes(aabbs);
        self.emit(aabbs, inv, is_static, out);
    }

    /// Counting sort of the grid boxes by bucket.
    fn build_grid(&mut self, aabbs: &[Aabb], inv: Real) {
        let grid_boxes = self.kind.iter().filter(|&&k| k == Kind::Grid).count();
        let buckets = (2 * grid_boxes).next_power_of_two().max(16);
        let mask = (buckets - 1) as u32;
        let g = &mut self.grid;
        g.start.clear();
        g.start.resize(buckets + 1, 0);
        self.bucket.clear();
        self.bucket.resize(aabbs.len(), 0);
        for (i, b) in aabbs.iter().enumerate() {
            if self.kind[i] == Kind::Grid {
                let cx = cell(b.min.x, inv);
                let bucket =
                    row_hash(cell(b.min.y, inv), cell(b.min.z, inv)).wrapping_add(cx as u32) & mask;
                self.bucket[i] = bucket;
                g.start[bucket as usize] += 1;
            }
        }
        // Inclusive prefix sums: `start[b]` is the end of bucket `b`; the scatter below, in
        // reverse input order, moves it back to the bucket's start.
        let mut sum = 0;
        for s in &mut g.start[..buckets] {
            sum += *s;
            *s = sum;
        }
        g.start[buckets] = sum;
        for v in g.min.iter_mut().chain(g.max.iter_mut()) {
            v.clear();
            v.resize(grid_boxes, 0.0);
        }
        g.id.clear();
        g.id.resize(grid_boxes, 0);
        for (i, b) in aabbs.iter().enumerate().rev() {
            if self.kind[i] == Kind::Grid {
                let s = &mut g.start[self.bucket[i] as usize];
                *s -= 1;
                let at = *s as usize;
                for k in 0..3 {
                    g.min[k][at] = b.min[k];
                    g.max[k][at] = b.max[k];
                }
                g.id[at] = i as u32;
            }
        }
    }

    /// Every pair with a side-list box in it, by testing that box against every other box;
    /// a pair of two side-list boxes is tested from the lower index only.
    fn pair_side_boxes(&mut self, aabbs: &[Aabb]) {
        self.side.clear();
        self.side.extend(
            self.kind
                .iter()
                .enumerate()
                .filter(|&(_, &k)| k == Kind::Side)
                .map(|(i, _)| i as u32),
        );
        self.side_pairs.clear();
        for &s in &self.side {
            let a = &aabbs[s as usize];
            for (j, (b, &kind)) in aabbs.iter().zip(&self.kind).enumerate() {
                let j = j as u32;
                let skip = kind == Kind::Never || (kind == Kind::Side && j <= s);
                if !skip && a.intersects(b) {
                    self.side_pairs.push((s.min(j), s.max(j)));
                }
            }
        }
        // Pairs are unique, so the unstable sort is deterministic.
        self.side_pairs.sort_unstable();
    }

    /// The pairs of each box `i` with the boxes `j > i`, in order of `i`, each box's partners
    /// sorted: the whole list comes out sorted.
    fn emit(
        &mut self,
        aabbs: &[Aabb],
        inv: Real,
        is_static: Option<&[bool]>,
        out: &mut Vec<(u32, u32)>,
    ) {
        let mask = (self.grid.start.len() - 2) as u32;
        let mut side_next = 0;
        for (i, a) in aabbs.iter().enumerate() {
            let i = i as u32;
            self.partners.clear();
            if self.kind[i as usize] == Kind::Grid {
                query(&self.grid, mask, a, i, inv, &mut self.partners);
            }
            while let Some(&(p, q)) = self.side_pairs.get(side_next) {
                if p != i {
                    break;
                }
                self.partners.push(q);
                side_next += 1;
            }
            if self.partners.is_empty() {
                continue;
            }
            self.partners.sort_unstable();
            self.partners.dedup();
            for &j in &self.partners {
                if is_static.is_none_or(|f| wanted(f, i, j)) {
                    out.push((i, j));
                }
            }
        }
    }
}

/// Pushes onto `partners` every grid box `j > i` that overlaps `a` (box `i`), perhaps more
/// than once (see the module documentation).
#[inline]
fn query(g: &Buckets, mask: u32, a: &Aabb, i: u32, inv: Real, partners: &mut Vec<u32>) {
    let lo = [cell(a.min.x, inv), cell(a.min.y, inv), cell(a.min.z, inv)];
    let hi = [cell(a.max.x, inv), cell(a.max.y, inv), cell(a.max.z, inv)];
    let buckets = mask as usize + 1;
    // Cells along x per row: `lo - 1 ..= hi`, 2 or 3 for a grid box.
    let run = (hi[0] - lo[0] + 2) as usize;
    for cz in lo[2] - 1..=hi[2] {
        for cy in lo[1] - 1..=hi[1] {
            let first = (row_hash(cy, cz).wrapping_add((lo[0] - 1) as u32) & mask) as usize;
            let end = first + run;
            if end <= buckets {
                scan(g, g.start[first]..g.start[end], a, i, partners);
            } else {
                scan(g, g.start[first]..g.start[buckets], a, i, partners);
                scan(g, g.start[0]..g.start[end - buckets], a, i, partners);
            }
        }
    }
}

/// The closed-interval test of `a` (box `i`) against the bucket-sorted boxes `range`.
#[inline]
fn scan(g: &Buckets, range: std::ops::Range<u32>, a: &Aabb, i: u32, partners: &mut Vec<u32>) {
    let range = range.start as usize..range.end as usize;
    let [min0, min1, min2] = &g.min;
    let [max0, max1, max2] = &g.max;
    for k in range {
        // Non-short-circuit `&`: branch-free but for the rare hit.
        let hit = (g.id[k] > i)
            & (min0[k] <= a.max.x)
            & (a.min.x <= max0[k])
            & (min1[k] <= a.max.y)
            & (a.min.y <= max1[k])
            & (min2[k] <= a.max.z)
            & (a.min.z <= max2[k]);
        if hit {
            partners.push(g.id[k]);
        }
    }
}

/// Every overlapping pair `(i, j)`, `i < j`, sorted ascending, by the step's broad phase
/// ([`BroadPhase`]); equals `brute_force_pairs`.
pub fn broad_phase_pairs(aabbs: &[Aabb]) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    BroadPhase::new().find_pairs(aabbs, &mut out);
    out
}

/// As `broad_phase_pairs`, leaving out pairs whose two boxes are both flagged in `is_static`.
pub fn broad_phase_pairs_filtered(
    aabbs: &[Aabb],
    is_static: &[bool],
) -> Result<Vec<(u32, u32)>, BroadPhaseError> {
    let mut out = Vec::new();
    BroadPhase::new().find_pairs_filtered(aabbs, is_static, &mut out)?;
    Ok(out)
}
