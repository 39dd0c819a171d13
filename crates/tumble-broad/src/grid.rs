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
//! memory; in a dense grid each box visits only the forward half of its neighbour cells, so
//! each pair is found once (`grid_query.rs`). The pairs found are then grouped by their
//! lower index (a counting sort), each group's partners sorted, and the groups written out
//! in order, merged with the side list's pairs: the list comes out sorted without a sort of
//! the whole list. Nothing depends on timing or threads: the result is the same set in the
//! same order on every run.

use tumble_geometry::{Aabb, Real};

use crate::cell_size::{Corners, Kind, cell_size, classify};
use crate::filter::{CollisionGroups, Filter, check_flags, check_groups};
use crate::grid_query::{Buckets, Entry, Layout, cell, query_dense, query_hashed, row_key};
use crate::{BroadPhaseError, collect_pairs};

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
    /// The pairs `(i, j)`, `i < j`, found in the grid, in the order found: the first
    /// `found_len` (the rest is room kept from earlier calls).
    found: Vec<(u32, u32)>,
    found_len: usize,
    /// Per box `i`, `first[i]..first[i + 1]`: its grid partners `j > i` in `partners`.
    first: Vec<u32>,
    /// The grid partners grouped by `i` (the counting sort of `found`), each group sorted.
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
        self.query_grid(inv);
        self.group(aabbs.len());
        self.emit(out, is_static);
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
                let bucket = self.bucket[i] as usize;
                g.entry[at] = Entry {
                    min: [b.min.x, b.min.y, b.min.z],
                    max: [b.max.x, b.max.y, b.max.z],
                    id: i as u32,
                    cell: if g.layout.dense {
                        Entry::pack(bucket, self.corners.span[i])
                    } else {
                        0
                    },
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

    /// Every overlapping pair of grid boxes, once, into `found[..found_len]`.
    fn query_grid(&mut self, inv: Real) {
        self.found_len = if self.grid.layout.dense {
            query_dense(&self.grid, &mut self.found)
        } else {
            query_hashed(&self.grid, inv, &mut self.found)
        };
    }

    /// Groups the found pairs by their lower index (a counting sort into `partners`); each
    /// group is sorted as it is written out.
    fn group(&mut self, n: usize) {
        let found = &self.found[..self.found_len];
        self.first.clear();
        self.first.resize(n + 1, 0);
        self.partners.clear();
        self.partners.resize(found.len(), 0);
        // Plain slices, so that the loops keep their pointers in registers.
        let (first, partners) = (&mut self.first[..], &mut self.partners[..]);
        for &(i, _) in found {
            first[i as usize] += 1;
        }
        // Inclusive prefix sums: `first[i]` is the end of group `i`; the scatter below moves
        // it back to the group's start.
        let mut sum = 0;
        for f in &mut first[..n] {
            sum += *f;
            *f = sum;
        }
        first[n] = sum;
        for &(i, j) in found {
            let f = &mut first[i as usize];
            *f -= 1;
            partners[*f as usize] = j;
        }
    }

    /// The pairs in order of `i`: each box's grid partners (filtered, sorted) merged with its
    /// side-list pairs.
    fn emit(&mut self, out: &mut Vec<(u32, u32)>, is_static: Option<Filter<'_>>) {
        out.reserve(self.partners.len() + self.side_pairs.len());
        let mut side = self.side_pairs.as_slice();
        for (i, w) in self.first.windows(2).enumerate() {
            let i = i as u32;
            let (s, mut e) = (w[0] as usize, w[1] as usize);
            if let Some(filter) = is_static.filter(|f| f.may_drop(i)) {
                let mut kept = s;
                for k in s..e {
                    let j = self.partners[k];
                    if filter.wants(i, j) {
                        self.partners[kept] = j;
                        kept += 1;
                    }
                }
                e = kept;
            }
            let grid = &mut self.partners[s..e];
            let k = side.iter().take_while(|p| p.0 == i).count();
            if k == 0 && grid.len() <= RANKED {
                if !grid.is_empty() {
                    emit_ranked(i, grid, out);
                }
                continue;
            }
            grid.sort_unstable();
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

/// Groups of at most this many partners are sorted by rank (`emit_ranked`).
const RANKED: usize = 16;

/// Appends `(i, j)` for every `j` of `group` (distinct, at most `RANKED`) to `out`, in
/// ascending `j`: each partner goes to its rank, the number of partners below it. Branch-free
/// and a fixed number of lanes, where an insertion sort of the dozen partners a box has in a
/// pile mispredicts about once per partner.
#[inline]
fn emit_ranked(i: u32, group: &[u32], out: &mut Vec<(u32, u32)>) {
    // Padding lanes hold `u32::MAX`, which is no box index (they fit below it): never below
    // a partner.
    let mut lanes = [u32::MAX; RANKED];
    lanes[..group.len()].copy_from_slice(group);
    let mut sorted = [(0, 0); RANKED];
    for &j in group {
        let rank: u32 = lanes.iter().map(|&x| u32::from(x < j)).sum();
        sorted[rank as usize] = (i, j);
    }
    out.extend_from_slice(&sorted[..group.len()]);
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
