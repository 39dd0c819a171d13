//! The kept list repaired after a few boxes left their fat boxes (module documentation of
//! `kept.rs`): Box2D v3 re-inserts only the proxies whose tight boxes left their fat ones; here
//! only the pairs of those boxes are found again, and the list stays the sorted list of every
//! pair of intersecting fat boxes that the filter wants.

use rayon::prelude::*;
use tumble_geometry::{Aabb, Point3, Real};

use super::{KeptPairs, PARALLEL_MIN, fat_box};
use crate::filter::{CollisionGroups, Filter};

impl KeptPairs {
    /// Gives each box of `movers` a new fat box and replaces its pairs in the kept list by
    /// the pairs of its new fat box with every fat box (the movers' new ones included), under
    /// the filter of `is_static` and `groups`; the list stays sorted.
    ///
    /// Why the list is then what a search on the fat boxes would give: a pair of two boxes
    /// that did not move is kept as it was, and both its fat boxes are unchanged; every pair
    /// with a mover is dropped and found again by testing the mover's new fat box against all
    /// the others. A fat box meets a mover's only if it meets the movers' joint bounds (the
    /// smallest box holding all of them), so one test against those skips the boxes far from
    /// every mover.
    pub(super) fn repair(
        &mut self,
        aabbs: &[Aabb],
        is_static: &[bool],
        groups: Option<&[CollisionGroups]>,
    ) {
        let filter = Filter { is_static, groups };
        // Until the new list is in place, `fat` and `pairs` do not belong together.
        self.valid = false;
        self.moved.resize(aabbs.len(), false);
        // `min` and `max` skip a NaN bound; a box with one meets nothing (every comparison
        // with NaN is false), so leaving it out of the joint bounds loses no pair.
        let mut joint = Aabb::new(
            Point3::from([Real::INFINITY; 3]),
            Point3::from([Real::NEG_INFINITY; 3]),
        );
        for &m in &self.movers {
            let f = fat_box(&aabbs[m as usize]);
            self.fat[m as usize] = f;
            self.moved[m as usize] = true;
            for k in 0..3 {
                joint.min[k] = joint.min[k].min(f.min[k]);
                joint.max[k] = joint.max[k].max(f.max[k]);
            }
        }
        // The movers' fat boxes by their lower bound along the joint bounds' longest side, so
        // that a box's test can stop at the first mover that starts beyond it; a mover with a
        // NaN bound meets nothing and is left out.
        let axis = (0..3)
            .max_by(|&a, &b| {
                let side = |k: usize| joint.max[k] - joint.min[k];
                side(a).total_cmp(&side(b))
            })
            .unwrap_or(0);
        self.mover_boxes.clear();
        self.mover_boxes.extend(
            self.movers
                .iter()
                .map(|&m| (self.fat[m as usize], m))
                .filter(|(f, _)| (0..3).all(|k| !f.min[k].is_nan() && !f.max[k].is_nan())),
        );
        self.mover_boxes
            .sort_unstable_by(|a, b| a.0.min[axis].total_cmp(&b.0.min[axis]).then(a.1.cmp(&b.1)));
        self.fresh.clear();
        let movers = Movers {
            boxes: &self.mover_boxes,
            moved: &self.moved,
            joint,
            axis,
            filter,
        };
        if self.fat.len() >= PARALLEL_MIN && rayon::current_num_threads() > 1 {
            // Each chunk of boxes finds its own pairs; the order does not matter (sorted
            // below).
            let chunk = PARALLEL_MIN / 4;
            self.fresh
                .par_extend(
                    self.fat
                        .par_chunks(chunk)
                        .enumerate()
                        .flat_map_iter(|(k, fat)| {
                            let mut found = Vec::new();
                            movers.pairs(fat, k * chunk, &mut found);
                            found
                        }),
                );
        } else {
            movers.pairs(&self.fat, 0, &mut self.fresh);
        }
        // Every fresh pair has a mover and no kept one has, so the two lists are disjoint and
        // merge in order. On the pool, each chunk of the kept list merges with the fresh
        // pairs from its first pair up to the next chunk's first, and the pieces join in
        // chunk order: the same list.
        self.fresh.sort_unstable();
        self.merged.clear();
        let (pairs, fresh, moved) = (&self.pairs, &self.fresh, &self.moved);
        if pairs.len() >= PARALLEL_MIN && rayon::current_num_threads() > 1 {
            let chunk = PARALLEL_MIN / 4;
            self.merged
                .par_extend(
                    pairs
                        .par_chunks(chunk)
                        .enumerate()
                        .flat_map_iter(|(k, part)| {
                            let from = match k {
                                0 => 0,
                                _ => fresh.partition_point(|&q| q < part[0]),
                            };
                            let to = match pairs.get((k + 1) * chunk) {
                                Some(&next) => fresh.partition_point(|&q| q < next),
                                None => fresh.len(),
                            };
                            let mut piece = Vec::with_capacity(part.len() + to - from);
                            merge(part, &fresh[from..to], moved, &mut piece);
                            piece
                        }),
                );
        } else {
            self.merged.reserve(pairs.len() + fresh.len());
            merge(pairs, fresh, moved, &mut self.merged);
        }
        std::mem::swap(&mut self.pairs, &mut self.merged);
        self.valid = true;
        for &m in &self.movers {
            self.moved[m as usize] = false;
        }
    }
}

/// What a repair tests every fat box against: the movers' new fat boxes sorted by their lower
/// bound along `axis`, their joint bounds, which boxes are movers, and the pair filter.
struct Movers<'a> {
    boxes: &'a [(Aabb, u32)],
    moved: &'a [bool],
    joint: Aabb,
    axis: usize,
    filter: Filter<'a>,
}

impl Movers<'_> {
    /// Appends to `out` every wanted pair of a mover's fat box with a box of `fat`, whose
    /// first box is box `first`; a pair of two movers only from the higher index's side.
    fn pairs(&self, fat: &[Aabb], first: usize, out: &mut Vec<(u32, u32)>) {
        let axis = self.axis;
        for (j, fat_j) in fat.iter().enumerate() {
            if !self.joint.intersects(fat_j) {
                continue;
            }
            let j = (first + j) as u32;
            for &(fat_m, m) in self.boxes {
                if fat_m.min[axis] > fat_j.max[axis] {
                    break;
                }
                if m == j || (self.moved[j as usize] && j < m) {
                    continue;
                }
                let (a, b) = (m.min(j), m.max(j));
                if fat_m.intersects(fat_j) && self.filter.wants(a, b) {
                    out.push((a, b));
                }
            }
        }
    }
}

/// Appends to `out` the pairs of `kept` with no box marked in `moved`, and every pair of
/// `fresh`, in order (both sorted, no pair in both).
fn merge(kept: &[(u32, u32)], fresh: &[(u32, u32)], moved: &[bool], out: &mut Vec<(u32, u32)>) {
    let mut fresh = fresh.iter().copied().peekable();
    for &p in kept {
        if moved[p.0 as usize] || moved[p.1 as usize] {
            continue;
        }
        while let Some(q) = fresh.next_if(|&q| q < p) {
            out.push(q);
        }
        out.push(p);
    }
    out.extend(fresh);
}

#[cfg(test)]
mod tests {
    use super::super::REPAIR_MAX;
    use super::*;
    use crate::brute_force_pairs_filtered;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use tumble_geometry::Vec3;

    /// A resting field of boxes in which, step after step, 1 to [`REPAIR_MAX`] boxes jump up
    /// to 3 m (out of their fat boxes, often onto each other and onto static boxes; some turned
    /// inside out, two given an infinite side), with collision groups on some of the run: every call's pairs equal brute force's, and the
    /// list is repaired on every such step, never searched. A repair that kept a mover's old
    /// pairs (a pair twice), missed a pair of two movers or of a mover and a box far in the
    /// list, broke the order, or ignored the filter fails here.
    #[test]
    fn repaired_lists_equal_brute_force_through_random_jumps() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let n = 1_500;
        let extent = 16.0;
        let mut aabbs: Vec<Aabb> = (0..n)
            .map(|_| {
                let c = Point3::new(
                    rng.random_range(0.0..extent),
                    rng.random_range(0.0..extent),
                    rng.random_range(0.0..extent),
                );
                let h = Vec3::new(
                    rng.random_range(0.1..0.6),
                    rng.random_range(0.1..0.6),
                    rng.random_range(0.1..0.6),
                );
                Aabb::new(c - h, c + h)
            })
            .collect();
        let is_static: Vec<bool> = (0..n).map(|_| rng.random_bool(0.15)).collect();
        let groups: Vec<CollisionGroups> = (0..n)
            .map(|_| match rng.random_range(0..4) {
                0 => CollisionGroups::new(0b01, 0b10),
                1 => CollisionGroups::new(0b10, 0b01),
                _ => CollisionGroups::ALL,
            })
            .collect();
        let mut kept = KeptPairs::new();
        let mut out = Vec::new();
        let mut mover_pairs = 0;
        for step in 0..240 {
            let grouped = (step / 60) % 2 == 1;
            let g = grouped.then_some(groups.as_slice());
            if step % 60 > 1 {
                // Jump a few boxes; the first of them lands on the second, so two movers
                // often pair.
                let count = rng.random_range(1..=REPAIR_MAX);
                let mut picked: Vec<usize> = (0..count).map(|_| rng.random_range(0..n)).collect();
                picked.sort_unstable();
                picked.dedup();
                for &k in &picked {
                    let d = Vec3::new(
                        rng.random_range(-3.0..3.0),
                        rng.random_range(-3.0..3.0),
                        rng.random_range(-3.0..3.0),
                    );
                    aabbs[k] = Aabb::new(aabbs[k].min + d, aabbs[k].max + d);
                }
                // Now and then a mover turned inside out along y (min above max), or given
                // an infinite side: the repair's joint bounds and its sort must still find
                // every pair brute force does.
                if step % 7 == 3 {
                    let b = &mut aabbs[picked[0]];
                    std::mem::swap(&mut b.min.y, &mut b.max.y);
                }
                if step == 30 || step == 150 {
                    aabbs[picked[0]].max.x = Real::INFINITY;
                }
                if picked.len() > 1 {
                    let (a, b) = (picked[0], picked[1]);
                    let d = aabbs[b].center() - aabbs[a].center() + Vec3::new(0.0, 0.2, 0.0);
                    // (Not from or onto a box with an infinite side: its centre is not finite.)
                    if d.iter().all(|x| x.is_finite()) {
                        aabbs[a] = Aabb::new(aabbs[a].min + d, aabbs[a].max + d);
                    }
                }
            }
            kept.find_pairs(&aabbs, &is_static, g, &mut out).unwrap();
            let expected: Vec<(u32, u32)> = brute_force_pairs_filtered(&aabbs, &is_static)
                .unwrap()
                .into_iter()
                .filter(|&(i, j)| g.is_none_or(|g| g[i as usize].interacts_with(g[j as usize])))
                .collect();
            assert_eq!(out, expected, "step {step}");
            if step % 60 > 1 && kept.repaired_last() {
                mover_pairs += kept
                    .movers
                    .iter()
                    .filter(|&&m| kept.movers.iter().any(|&o| expected.contains(&(m, o))))
                    .count();
            }
            // The first call of each group setting searches (the groups changed), the next
            // reuses the list as it is; every later call has movers and repairs it, unless
            // its one mover stayed inside its fat box (a box with an infinite side can).
            if step % 60 > 1 {
                assert!(kept.reused_last(), "step {step}");
            }
        }
        assert_eq!(kept.counts().0, 4, "one search per group setting");
        assert!(kept.repairs() >= 200, "{} repairs", kept.repairs());
        assert!(mover_pairs >= 20, "{mover_pairs} pairs of two movers");
    }
}
