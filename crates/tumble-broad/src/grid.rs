//! The broad phase of the step: a uniform grid of cells about one box across, with a side
//! list for the few boxes much larger than the rest.
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
//! When the grid boxes' bounding grid has at most `DENSE_CELLS_PER_BOX` cells per box, every
//! cell has a bucket of its own, x fastest; otherwise (a sparse or widely spread scene) rows
//! of cells are hashed into a power-of-two table, a row's cells onto consecutive buckets.
//! Either way the cells of one query row are one contiguous run of the bucket-sorted boxes.
//! In the hashed table other rows' boxes share the run; each box carries its row's exact
//! key, so it is taken from its own row only, once.
//!
//! The boxes are queried in bucket order, so that neighbouring queries read neighbouring
//! memory; each box keeps its partners `j > i` as a sorted run, and the runs are written
//! out in order of `i`, merged with the side list's pairs: the list comes out sorted
//! without a sort of the whole list. Nothing depends on timing or threads: the result is
//! the same set in the same order on every run.

use tumble_geometry::{Aabb, Real};

use crate::cell_size::{Corners, Kind, cell_size, classify};
use crate::filter::{CollisionGroups, Filter, check_flags, check_groups};
use crate::{BroadPhaseError, collect_pairs};

/// Cell coordinates are clamped to `±CELL_LIMIT`, so that `lo - 1` cannot overflow; the
/// clamp is monotone, which is all the search needs.
const CELL_LIMIT: Real = (1 << 30) as Real;

/// The cell of coordinate `x` for `inv = 1 / h`: `floor(x / h)`, clamped. Monotone in `x`.
#[inline]
fn cell(x: Real, inv: Real) -> i32 {
    // Clamped first, so the truncation is exact and cannot saturate; truncation rounds
    // towards zero, one less below zero gives the floor (no libm call).
    let v = (x * inv).clamp(-CELL_LIMIT, CELL_LIMIT);
    let t = v as i32;
    t - i32::from((t as Real) > v)
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

/// The exact identity of a row of cells, to tell its boxes from those of other rows hashed
/// into the same buckets.
#[inline]
fn row_key(cy: i32, cz: i32) -> u64 {
    (u64::from(cy as u32) << 32) | u64::from(cz as u32)
}

/// One grid box, as stored in bucket order: its bounds and index, one 32-byte line.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
struct Entry {
    min: [Real; 3],
    max: [Real; 3],
    id: u32,
}

/// Dense grids of at most this many cells per grid box are used as they are; larger ones
/// (a sparse or widely spread scene) are hashed into about one bucket per box.
const DENSE_CELLS_PER_BOX: u64 = 8;

/// How cells map to buckets.
#[derive(Clone, Copy, Debug, Default)]
struct Layout {
    /// One bucket per cell of the boxes' bounding grid, x fastest, then y, then z: no two
    /// cells share a bucket. Otherwise rows of cells are hashed (`row_hash`).
    dense: bool,
    /// Dense: the lowest cell on each axis.
    origin: [i32; 3],
    /// Dense: cells per axis.
    dims: [i32; 3],
    /// Number of buckets (hashed: a power of two).
    buckets: usize,
}

impl Layout {
    /// The layout for grid boxes whose lower corners lie in the cells `lo..=hi`.
    fn new(lo: [i32; 3], hi: [i32; 3], boxes: usize) -> Self {
        let dims: [i64; 3] = std::array::from_fn(|k| i64::from(hi[k]) - i64::from(lo[k]) + 1);
        let cells = dims.iter().map(|&d| d.max(1) as u64).product::<u64>();
        if boxes > 0 && cells <= DENSE_CELLS_PER_BOX * boxes as u64 + 64 {
            Layout {
                dense: true,
                origin: lo,
                dims: dims.map(|d| d as i32),
                buckets: cells as usize,
            }
        } else {
            Layout {
                dense: false,
                buckets: boxes.next_power_of_two().max(16),
                ..Layout::default()
            }
        }
    }

    /// The bucket of cell `c` (dense: a cell within the bounds).
    #[inline]
    fn bucket(&self, c: [i32; 3]) -> usize {
        if self.dense {
            let [x, y, z]: [usize; 3] = std::array::from_fn(|k| (c[k] - self.origin[k]) as usize);
            x + self.dims[0] as usize * (y + self.dims[1] as usize * z)
        } else {
            (row_hash(c[1], c[2]).wrapping_add(c[0] as u32) as usize) & (self.buckets - 1)
        }
    }
}

/// The grid boxes sorted by bucket.
#[derive(Clone, Debug, Default)]
struct Buckets {
    layout: Layout,
    /// `start[b]..start[b + 1]`: the boxes of bucket `b`, in `entry` and `row`.
    start: Vec<u32>,
    entry: Vec<Entry>,
    /// The row key of each entry's cell.
    row: Vec<u64>,
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
    /// The grid boxes' lower-corner cells.
    corners: Corners,
    /// Per box, in input order: its bucket (grid boxes only).
    bucket: Vec<u32>,
    /// The grid boxes by bucket.
    grid: Buckets,
    /// Indices of the side-list boxes, ascending.
    side: Vec<u32>,
    /// Every pair with a side-list box in it, sorted.
    side_pairs: Vec<(u32, u32)>,
    /// The partners `j > i` found in the grid, box after box in bucket order, each box's run
    /// sorted.
    partners: Vec<u32>,
    /// Per box, in input order: where its run of `partners` starts and ends.
    run: Vec<(u32, u32)>,
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

    /// The cell size the last query used (0 before the first).
    pub fn cell_size(&self) -> Real {
        self.cell
    }

    /// How many boxes of the last query went to the side list (tested against every box).
    pub fn oversized(&self) -> usize {
        self.side.len()
    }

    /// Whether the last query's grid had a bucket per cell (else rows were hashed).
    #[cfg(test)]
    pub(crate) fn was_dense(&self) -> bool {
        self.grid.layout.dense
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
        let filter = Filter {
            is_static,
            groups: None,
        };
        self.run(aabbs, Some(filter), out);
        Ok(())
    }

    /// As `find_pairs_filtered`, also leaving out the pairs whose [`CollisionGroups`] do not
    /// interact (one entry per box).
    pub fn find_pairs_grouped(
        &mut self,
        aabbs: &[Aabb],
        is_static: &[bool],
        groups: &[CollisionGroups],
        out: &mut Vec<(u32, u32)>,
    ) -> Result<(), BroadPhaseError> {
        check_flags(aabbs, is_static)?;
        check_groups(aabbs, groups)?;
        let filter = Filter {
            is_static,
            groups: Some(groups),
        };
        self.run(aabbs, Some(filter), out);
        Ok(())
    }

    fn run(&mut self, aabbs: &[Aabb], is_static: Option<Filter<'_>>, out: &mut Vec<(u32, u32)>) {
        out.clear();
        assert!(
            aabbs.len() < u32::MAX as usize,
            "box indices must fit in u32"
        );
        let h = cell_size(aabbs, &mut self.sample);
        self.cell = h;
        let inv = 1.0 / h;
        classify(aabbs, inv, cell, &mut self.kind, &mut self.corners);
        self.build_grid(aabbs);
        self.pair_side_boxes(aabbs, is_static);
        self.query_grid(aabbs.len(), inv, is_static);
        self.emit(out);
    }

    /// Counting sort of the grid boxes by bucket.
    fn build_grid(&mut self, aabbs: &[Aabb]) {
        let c = &self.corners;
        let grid_boxes = c.count;
        let g = &mut self.grid;
        g.layout = Layout::new(c.lo, c.hi, grid_boxes);
        let buckets = g.layout.buckets;
        g.start.clear();
        g.start.resize(buckets + 1, 0);
        self.bucket.clear();
        self.bucket.resize(aabbs.len(), 0);
        for (i, &c) in self.corners.cell.iter().enumerate() {
            if self.kind[i] == Kind::Grid {
                let bucket = g.layout.bucket(c);
                self.bucket[i] = bucket as u32;
                g.start[bucket] += 1;
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
        g.entry.clear();
        g.entry.resize(grid_boxes, Entry::default());
        g.row.clear();
        g.row.resize(if g.layout.dense { 0 } else { grid_boxes }, 0);
        for (i, b) in aabbs.iter().enumerate().rev() {
            if self.kind[i] == Kind::Grid {
                let s = &mut g.start[self.bucket[i] as usize];
                *s -= 1;
                let at = *s as usize;
                g.entry[at] = Entry {
                    min: [b.min.x, b.min.y, b.min.z],
                    max: [b.max.x, b.max.y, b.max.z],
                    id: i as u32,
                };
                if !g.layout.dense {
                    let c = self.corners.cell[i];
                    g.row[at] = row_key(c[1], c[2]);
                }
            }
        }
    }

    /// Every wanted pair with a side-list box in it, by testing that box against every other
    /// box; a pair of two side-list boxes is tested from the lower index only.
    fn pair_side_boxes(&mut self, aabbs: &[Aabb], is_static: Option<Filter<'_>>) {
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
                    let pair = (s.min(j), s.max(j));
                    if is_static.is_none_or(|f| f.wants(pair.0, pair.1)) {
                        self.side_pairs.push(pair);
                    }
                }
            }
        }
        // Pairs are unique, so the unstable sort is deterministic.
        self.side_pairs.sort_unstable();
    }

    /// The wanted partners `j > i` of every grid box `i`, queried in bucket order (so that
    /// neighbouring queries read neighbouring memory), each box's run sorted.
    fn query_grid(&mut self, n: usize, inv: Real, is_static: Option<Filter<'_>>) {
        self.run.clear();
        self.run.resize(n, (0, 0));
        self.partners.clear();
        let g = &self.grid;
        for a in &g.entry {
            let first = self.partners.len();
            if g.layout.dense {
                query_dense(g, a, inv, &mut self.partners);
            } else {
                query_hashed(g, a, inv, &mut self.partners);
            }
            if let Some(filter) = is_static.filter(|f| f.may_drop(a.id)) {
                let mut kept = first;
                for k in first..self.partners.len() {
                    let j = self.partners[k];
                    if filter.wants(a.id, j) {
                        self.partners[kept] = j;
                        kept += 1;
                    }
                }
                self.partners.truncate(kept);
            }
            self.partners[first..].sort_unstable();
            self.run[a.id as usize] = (first as u32, self.partners.len() as u32);
        }
    }

    /// The pairs in order of `i`: each box's grid run merged with its side-list pairs.
    fn emit(&self, out: &mut Vec<(u32, u32)>) {
        let mut side = self.side_pairs.as_slice();
        for (i, &(s, e)) in self.run.iter().enumerate() {
            let i = i as u32;
            let grid = &self.partners[s as usize..e as usize];
            let k = side.iter().take_while(|p| p.0 == i).count();
            if k == 0 {
                out.extend(grid.iter().map(|&j| (i, j)));
                continue;
            }
            let (mine, rest) = side.split_at(k);
            side = rest;
            // Two sorted runs of distinct partners: merge.
            let (mut g, mut m) = (grid.iter().peekable(), mine.iter().peekable());
            loop {
                let j = match (g.peek(), m.peek()) {
                    (Some(&&a), Some(&&(_, b))) if a < b => g.next().copied(),
                    (_, Some(_)) => m.next().map(|p| p.1),
                    (Some(_), None) => g.next().copied(),
                    (None, None) => break,
                };
                out.extend(j.map(|j| (i, j)));
            }
        }
    }
}

/// Pushes onto `partners` every grid box `j > i` that overlaps `a` (box `i`) in a dense
/// grid: each cell has its own bucket, and the query is clipped to the grid's bounds.
#[inline]
fn query_dense(g: &Buckets, a: &Entry, inv: Real, partners: &mut Vec<u32>) {
    let l = &g.layout;
    let lo = a.min.map(|v| cell(v, inv));
    let hi = a.max.map(|v| cell(v, inv));
    let from: [i32; 3] = std::array::from_fn(|k| (lo[k] - 1).max(l.origin[k]));
    let to: [i32; 3] = std::array::from_fn(|k| hi[k].min(l.origin[k] + l.dims[k] - 1));
    if from[0] > to[0] {
        return;
    }
    let run = (to[0] - from[0] + 1) as usize;
    // At most 3 x 3 rows for a grid box: their runs of boxes first, then one pass over them.
    let mut rows = [(0usize, 0usize); 9];
    let mut count = 0;
    let mut total = 0;
    for cz in from[2]..=to[2] {
        for cy in from[1]..=to[1] {
            let first = l.bucket([from[0], cy, cz]);
            let (s, e) = (g.start[first] as usize, g.start[first + run] as usize);
            rows[count] = (s, e);
            count += 1;
            total += e - s;
        }
    }
    // Branch-free: every candidate is written, the count moves on a hit only (half the
    // neighbours of a box in a pile come after it: a branch would mispredict).
    let mut kept = partners.len();
    partners.resize(kept + total, 0);
    for &(s, e) in &rows[..count] {
        for b in &g.entry[s..e] {
            partners[kept] = b.id;
            kept += usize::from(overlaps(a, b));
        }
    }
    partners.truncate(kept);
}

/// As `query_dense` in a hashed grid: rows of cells share buckets, so a box is taken only
/// from the row of cells it is stored in (once each).
#[inline]
fn query_hashed(g: &Buckets, a: &Entry, inv: Real, partners: &mut Vec<u32>) {
    let lo = a.min.map(|v| cell(v, inv));
    let hi = a.max.map(|v| cell(v, inv));
    let buckets = g.layout.buckets;
    let mask = (buckets - 1) as u32;
    // Cells along x per row: `lo - 1 ..= hi`, 2 or 3 for a grid box.
    let run = (hi[0] - lo[0] + 2) as usize;
    for cz in lo[2] - 1..=hi[2] {
        for cy in lo[1] - 1..=hi[1] {
            let first = (row_hash(cy, cz).wrapping_add((lo[0] - 1) as u32) & mask) as usize;
            let end = first + run;
            let key = row_key(cy, cz);
            if end <= buckets {
                scan_row(g, g.start[first]..g.start[end], a, key, partners);
            } else {
                scan_row(g, g.start[first]..g.start[buckets], a, key, partners);
                scan_row(g, g.start[0]..g.start[end - buckets], a, key, partners);
            }
        }
    }
}

/// The closed-interval test of `a` against the bucket-sorted boxes `range` of row `key`.
#[inline]
fn scan_row(
    g: &Buckets,
    range: std::ops::Range<u32>,
    a: &Entry,
    key: u64,
    partners: &mut Vec<u32>,
) {
    let range = range.start as usize..range.end as usize;
    for (b, &row) in g.entry[range.clone()].iter().zip(&g.row[range]) {
        if overlaps(a, b) && row == key {
            partners.push(b.id);
        }
    }
}

/// `b` comes after `a` and overlaps it: `Aabb::intersects`, closed intervals.
#[inline]
fn overlaps(a: &Entry, b: &Entry) -> bool {
    // Non-short-circuit `&`: branch-free but for the rare hit.
    (b.id > a.id)
        & (b.min[0] <= a.max[0])
        & (a.min[0] <= b.max[0])
        & (b.min[1] <= a.max[1])
        & (a.min[1] <= b.max[1])
        & (b.min[2] <= a.max[2])
        & (a.min[2] <= b.max[2])
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
    collect_pairs(|out| BroadPhase::new().find_pairs_filtered(aabbs, is_static, out))
}

/// As `broad_phase_pairs_filtered`, also leaving out the pairs whose [`CollisionGroups`] do
/// not interact.
pub fn broad_phase_pairs_grouped(
    aabbs: &[Aabb],
    is_static: &[bool],
    groups: &[CollisionGroups],
) -> Result<Vec<(u32, u32)>, BroadPhaseError> {
    collect_pairs(|out| BroadPhase::new().find_pairs_grouped(aabbs, is_static, groups, out))
}
