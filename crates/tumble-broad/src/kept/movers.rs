//! Which boxes left their enlarged ("fat") boxes since the kept list was made, and so whether
//! the list is reused, repaired or searched again (module documentation of `kept.rs`); and the
//! fat box itself.

use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;
use tumble_geometry::{Aabb, Real};

use super::{FAT_FRACTION, Kept, KeptPairs, PARALLEL_MIN, REPAIR_MAX};
use crate::filter::CollisionGroups;

impl KeptPairs {
    /// Whether the kept list answers this call (same boxes count, flags and groups, every box
    /// inside its fat box), can be repaired (the same, but at most [`REPAIR_MAX`] boxes left
    /// their fat boxes: those are in `movers`), or a search must run.
    pub(super) fn kept(
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
