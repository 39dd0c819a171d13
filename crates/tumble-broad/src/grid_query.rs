//! The grid's cells, buckets and queries (the search of `grid.rs`).
//!
//! Dense grids (a bucket per cell) are searched from one side: box `a` visits only the
//! neighbour cells that come after its own in bucket order (the forward half of its 3 x 3 x 3
//! neighbourhood) and, in its own cell, the boxes stored after it. Two grid boxes overlap
//! only if their lower-corner cells differ by at most one on every axis, so each
//! overlapping pair is found exactly once, from the box whose cell (or, in one cell, whose
//! place in the bucket) comes first. Hashed grids are searched from both sides, keeping
//! `j > i`. Either way a found pair is written `(lower index, higher index)`, and the caller
//! groups them by the lower index.

use tumble_geometry::Real;

/// Cell coordinates are clamped to `±CELL_LIMIT`, so that `lo - 1` cannot overflow; the
/// clamp is monotone, which is all the search needs.
const CELL_LIMIT: Real = (1 << 30) as Real;

/// The cell of coordinate `x` for `inv = 1 / h`: `floor(x / h)`, clamped. Monotone in `x`.
#[inline]
pub(crate) fn cell(x: Real, inv: Real) -> i32 {
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
pub(crate) fn row_key(cy: i32, cz: i32) -> u64 {
    (u64::from(cy as u32) << 32) | u64::from(cz as u32)
}

/// Bits of `Entry::cell` holding the bucket; the three above it hold the box's span.
const BUCKET_BITS: u32 = 29;

/// One grid box, as stored in bucket order: its bounds, index, and (dense grids) its bucket
/// and span; one 32-byte line.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
pub(crate) struct Entry {
    pub(crate) min: [Real; 3],
    pub(crate) max: [Real; 3],
    pub(crate) id: u32,
    /// Dense grids: the bucket in the low `BUCKET_BITS` bits, then the span bits of
    /// `Corners::span` (x, y, z).
    pub(crate) cell: u32,
}

impl Entry {
    /// The packed `cell` of a box in `bucket` (dense grids, `bucket < 2^BUCKET_BITS`) with
    /// span bits `span`.
    #[inline]
    pub(crate) fn pack(bucket: usize, span: u8) -> u32 {
        bucket as u32 | (u32::from(span) << BUCKET_BITS)
    }
}

/// Dense grids of at most this many cells per grid box are used as they are; larger ones
/// (a sparse or widely spread scene) are hashed into about one bucket per box.
const DENSE_CELLS_PER_BOX: u64 = 8;

/// How cells map to buckets.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Layout {
    /// One bucket per cell of the boxes' bounding grid grown by one cell on every side, x
    /// fastest, then y, then z: no two cells share a bucket, and every neighbour of a grid
    /// box's cell has a bucket. Otherwise rows of cells are hashed (`row_hash`).
    pub(crate) dense: bool,
    /// Dense: the lowest cell on each axis (one below the lowest lower corner).
    origin: [i32; 3],
    /// Dense: cells per axis.
    dims: [i32; 3],
    /// Number of buckets (hashed: a power of two).
    pub(crate) buckets: usize,
}

impl Layout {
    /// The layout for grid boxes whose lower corners lie in the cells `lo..=hi`.
    pub(crate) fn new(lo: [i32; 3], hi: [i32; 3], boxes: usize) -> Self {
        let span: [u64; 3] =
            std::array::from_fn(|k| (i64::from(hi[k]) - i64::from(lo[k]) + 1).max(1) as u64);
        let cells = span.iter().fold(1u64, |p, &d| p.saturating_mul(d));
        let padded = span.iter().fold(1u64, |p, &d| p.saturating_mul(d + 2));
        if boxes > 0
            && cells <= DENSE_CELLS_PER_BOX * boxes as u64 + 64
            && padded < 1 << BUCKET_BITS
        {
            Layout {
                dense: true,
                origin: lo.map(|c| c - 1),
                dims: span.map(|d| d as i32 + 2),
                buckets: padded as usize,
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
    pub(crate) fn bucket(&self, c: [i32; 3]) -> usize {
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
pub(crate) struct Buckets {
    pub(crate) layout: Layout,
    /// `start[b]..start[b + 1]`: the boxes of bucket `b`, in `entry` and `row`.
    pub(crate) start: Vec<u32>,
    pub(crate) entry: Vec<Entry>,
    /// Hashed grids: the row key of each entry's cell.
    pub(crate) row: Vec<u64>,
}

/// Every overlapping pair of grid boxes in a dense grid, each once, written to the start of
/// `found` as `(lower index, higher index)`; returns how many. Each box is tested against the
/// boxes after it in its own cell and in the forward half of its neighbour cells. `found`
/// keeps its length (grown when short), so that a reused buffer is not refilled each call.
pub(crate) fn query_dense(g: &Buckets, found: &mut Vec<(u32, u32)>) -> usize {
    let dims = g.layout.dims;
    // Bucket steps of one cell along y and z.
    let (y, z) = (dims[0] as usize, (dims[0] * dims[1]) as usize);
    let (start, entry) = (&g.start[..], &g.entry[..]);
    let mut kept = 0;
    for (p, a) in entry.iter().enumerate() {
        let b = (a.cell & ((1 << BUCKET_BITS) - 1)) as usize;
        let span = a.cell >> BUCKET_BITS;
        let [sx, sy, sz] = [span & 1, (span >> 1) & 1, span >> 2].map(|s| s as usize);
        // A partner's lower corner is at most one cell below `a`'s and at most `a`'s upper
        // corner's cell above: x from `cx - 1` to `cx + sx` in the rows after `a`'s own.
        // Own row: the boxes after `a` in its cell, then the next cell's if `a` reaches it.
        let mut ranges = [(0usize, 0usize); 5];
        ranges[0] = (p + 1, start[b + 1 + sx] as usize);
        let mut count = 1;
        let mut row = |first: usize| {
            ranges[count] = (start[first] as usize, start[first + 2 + sx] as usize);
            count += 1;
        };
        if sy == 1 {
            row(b + y - 1);
        }
        if sz == 1 {
            // The layer above: rows `cy - 1 ..= cy + sy`.
            for dy in 0..2 + sy {
                row(b + z + dy * y - y - 1);
            }
        }
        let total: usize = ranges[..count].iter().map(|&(s, e)| e - s).sum();
        // Branch-free: every candidate is written, the count moves on a hit only.
        if found.len() < kept + total {
            found.resize(2 * (kept + total), (0, 0));
        }
        for &(s, e) in &ranges[..count] {
            for c in &entry[s..e] {
                found[kept] = (a.id.min(c.id), a.id.max(c.id));
                kept += usize::from(overlaps(a, c));
            }
        }
    }
    kept
}

/// Every overlapping pair of grid boxes in a hashed grid, as `(i, j)`, `i < j`, into `found`
/// (cleared first); returns how many. Rows of cells share buckets, so a box is taken only
/// from the row of cells it is stored in (once each), and each box keeps its partners after
/// it.
pub(crate) fn query_hashed(g: &Buckets, inv: Real, found: &mut Vec<(u32, u32)>) -> usize {
    found.clear();
    let buckets = g.layout.buckets;
    let mask = (buckets - 1) as u32;
    for a in &g.entry {
        let lo = a.min.map(|v| cell(v, inv));
        let hi = a.max.map(|v| cell(v, inv));
        // Cells along x per row: `lo - 1 ..= hi`, 2 or 3 for a grid box.
        let run = (hi[0] - lo[0] + 2) as usize;
        for cz in lo[2] - 1..=hi[2] {
            for cy in lo[1] - 1..=hi[1] {
                let first = (row_hash(cy, cz).wrapping_add((lo[0] - 1) as u32) & mask) as usize;
                let end = first + run;
                let key = row_key(cy, cz);
                if end <= buckets {
                    scan_row(g, g.start[first]..g.start[end], a, key, found);
                } else {
                    scan_row(g, g.start[first]..g.start[buckets], a, key, found);
                    scan_row(g, g.start[0]..g.start[end - buckets], a, key, found);
                }
            }
        }
    }
    found.len()
}

/// The closed-interval test of `a` against the bucket-sorted boxes `range` of row `key`,
/// keeping the boxes after `a`.
#[inline]
fn scan_row(
    g: &Buckets,
    range: std::ops::Range<u32>,
    a: &Entry,
    key: u64,
    found: &mut Vec<(u32, u32)>,
) {
    let range = range.start as usize..range.end as usize;
    for (b, &row) in g.entry[range.clone()].iter().zip(&g.row[range]) {
        if (b.id > a.id) & overlaps(a, b) && row == key {
            found.push((a.id, b.id));
        }
    }
}

/// `Aabb::intersects` on two entries: closed intervals.
#[inline]
fn overlaps(a: &Entry, b: &Entry) -> bool {
    // Non-short-circuit `&`: branch-free but for the rare hit.
    (b.min[0] <= a.max[0])
        & (a.min[0] <= b.max[0])
        & (b.min[1] <= a.max[1])
        & (a.min[1] <= b.max[1])
        & (b.min[2] <= a.max[2])
        & (a.min[2] <= b.max[2])
}
