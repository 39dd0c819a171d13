//! `sweep_pairs`: the sweep of sweep-and-prune over bodies sorted by AABB lower bound, and
//! `long_pairs`: the long boxes it leaves out (`shaders/common/sweep.wgsl`), against all.

use crate::constants::{LONG_BOX_FACTOR, MAX_LONG_BOXES};
use crate::kernel::KernelSpec;
use crate::kernels::write_sort_keys::sweep_key;
use crate::layout::{BODY_STATIC, BODY_WORLD_SHIFT, GpuShape, GpuSweepBox};
use crate::shader::file;

/// The kernel: one thread per sorted body, appending pairs through an atomic counter.
pub static SWEEP_PAIRS: KernelSpec = KernelSpec::new(file("sweep_pairs.wgsl"));

/// The kernel pairing the long boxes: one thread per sorted body, against each long box.
pub static LONG_PAIRS: KernelSpec = KernelSpec::new(file("long_pairs.wgsl"));

/// Bytes of the long box list: its count, then [`MAX_LONG_BOXES`] sorted positions.
pub const LONG_BOXES_BYTES: u64 = 4 * (1 + MAX_LONG_BOXES as u64);

/// The sweep-axis length past which a box is long: [`LONG_BOX_FACTOR`] times the median
/// body's diameter (the longest an AABB of it gets, whatever its rotation). The median, so
/// that the long boxes themselves do not raise it. Infinite (no box is long) without bodies.
pub fn long_extent(shapes: &[GpuShape]) -> f32 {
    let mut diameters: Vec<f32> = shapes
        .iter()
        .map(|s| 2.0 * (s.hx * s.hx + s.hy * s.hy + s.hz * s.hz).sqrt())
        .collect();
    if diameters.is_empty() {
        return f32::INFINITY;
    }
    let middle = diameters.len() / 2;
    let (_, median, _) = diameters.select_nth_unstable_by(middle, f32::total_cmp);
    LONG_BOX_FACTOR * *median
}

/// The CPU twin of [`SWEEP_PAIRS`] followed by the canonical sort: every overlapping pair
/// that is not static-static, as `(smaller, larger)`, ascending, from the boxes in sweep
/// order (closed intervals; the sweep axis is implied by the order). It is
/// [`split_sweep_pairs_cpu`] with no box long.
pub fn sweep_pairs_cpu(boxes: &[GpuSweepBox]) -> Vec<(u32, u32)> {
    split_sweep_pairs_cpu(boxes, f32::INFINITY)
}

/// The CPU twin of `gather_sweep_boxes`' long box list, [`SWEEP_PAIRS`] and [`LONG_PAIRS`]
/// as the GPU runs them with `long_extent` (in list order; the GPU's list order varies,
/// the pair set does not), followed by the canonical sort: equal to [`sweep_pairs_cpu`].
pub fn split_sweep_pairs_cpu(boxes: &[GpuSweepBox], long_extent: f32) -> Vec<(u32, u32)> {
    split_sweep_pairs_in_worlds_cpu(boxes, long_extent, 0)
}

/// [`split_sweep_pairs_cpu`] for boxes sorted by [`sweep_key`] with `world_bits` bits of world
/// (each box's world in its flags): as the GPU runs it, each box scans while the candidate's
/// key is not past its upper bound's, and pairs only boxes of one world.
pub fn split_sweep_pairs_in_worlds_cpu(
    boxes: &[GpuSweepBox],
    long_extent: f32,
    world_bits: u32,
) -> Vec<(u32, u32)> {
    let world = |b: &GpuSweepBox| b.flags >> BODY_WORLD_SHIFT;
    let long_at = |b: &GpuSweepBox| b.hi_0 - b.lo_0 > long_extent;
    let long: Vec<usize> = (0..boxes.len()).filter(|&p| long_at(&boxes[p])).collect();
    let listed = long.len() <= MAX_LONG_BOXES as usize;
    let is_long = |b: &GpuSweepBox| listed && long_at(b);
    let overlap_12 = |a: &GpuSweepBox, b: &GpuSweepBox| {
        b.lo_1 <= a.hi_1 && a.lo_1 <= b.hi_1 && b.lo_2 <= a.hi_2 && a.lo_2 <= b.hi_2
    };
    let both_static = |a: &GpuSweepBox, b: &GpuSweepBox| a.flags & b.flags & BODY_STATIC != 0;
    let mut pairs = Vec::new();
    let mut push = |a: &GpuSweepBox, b: &GpuSweepBox| {
        pairs.push((a.body.min(b.body), a.body.max(b.body)));
    };
    for (p, me) in boxes.iter().enumerate() {
        if is_long(me) {
            continue;
        }
        let hi_key = sweep_key(world(me), me.hi_0, world_bits);
        for other in &boxes[p + 1..] {
            if sweep_key(world(other), other.lo_0, world_bits) > hi_key {
                break;
            }
            // The keys order the bounds only to their kept bits: both sides are tested, as
            // on the GPU.
            if !is_long(other)
                && other.lo_0 <= me.hi_0
                && other.hi_0 >= me.lo_0
                && overlap_12(me, other)
                && !both_static(me, other)
            {
                push(me, other);
            }
        }
    }
    if listed {
        for (q, me) in boxes.iter().enumerate() {
            for &p in &long {
                let l = &boxes[p];
                if p == q || (is_long(me) && me.body < l.body) {
                    continue;
                }
                let overlaps = l.lo_0 <= me.hi_0 && me.lo_0 <= l.hi_0 && overlap_12(me, l);
                if overlaps && world(me) == world(l) && !both_static(me, l) {
                    push(me, l);
                }
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::gather_sweep_boxes::gather_sweep_boxes_cpu;
    use crate::kernels::radix_sort::radix_sort_cpu;
    use crate::kernels::write_sort_keys::{write_sort_keys_cpu, write_sort_keys_in_worlds_cpu};
    use crate::layout::{GpuAabb, GpuShape};
    use rand::{Rng, SeedableRng};
    use tumble_geometry::Aabb;

    #[test]
    fn cpu_twin_equals_the_brute_force_reference() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2);
        let n = 500;
        let aabbs: Vec<GpuAabb> = (0..n)
            .map(|_| {
                let c: [f32; 3] = std::array::from_fn(|_| rng.random_range(0.0..10.0));
                let h: [f32; 3] = std::array::from_fn(|_| rng.random_range(0.1..0.8));
                GpuAabb {
                    min: [c[0] - h[0], c[1] - h[1], c[2] - h[2], 0.0],
                    max: [c[0] + h[0], c[1] + h[1], c[2] + h[2], 0.0],
                }
            })
            .collect();
        let shapes: Vec<GpuShape> = (0..n)
            .map(|i| GpuShape {
                flags: if i % 7 == 0 { BODY_STATIC } else { 0 },
                ..Default::default()
            })
            .collect();
        let statics: Vec<bool> = shapes.iter().map(GpuShape::is_static).collect();
        let boxes: Vec<Aabb> = aabbs.iter().map(crate::kernels::aabb_from_gpu).collect();
        let want = tumble_broad::brute_force_pairs_filtered(&boxes, &statics).unwrap();
        assert!(want.len() > n / 2, "a scene with pairs");
        for axis in 0..3 {
            let (keys, values) = write_sort_keys_cpu(&aabbs, axis);
            let (_, order) = radix_sort_cpu(&keys, &values, 32);
            let boxes = gather_sweep_boxes_cpu(&aabbs, &shapes, &order, axis);
            assert_eq!(sweep_pairs_cpu(&boxes), want);
        }
    }

    /// `count` random small boxes in a 10 m cube, then `long` slabs 8 m long along x, 0.2 m
    /// thick, across the cube at random heights (static every third); static every seventh.
    fn boxes_with_slabs(seed: u64, count: usize, long: usize) -> (Vec<GpuAabb>, Vec<GpuShape>) {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut aabbs = Vec::new();
        let mut shapes = Vec::new();
        for i in 0..count + long {
            let slab = i >= count;
            let c: [f32; 3] = std::array::from_fn(|_| rng.random_range(0.0..10.0));
            let h: [f32; 3] = if slab {
                [4.0, 0.1, rng.random_range(1.0..5.0)]
            } else {
                std::array::from_fn(|_| rng.random_range(0.1..0.5))
            };
            let centre = if slab { [5.0, c[1], c[2]] } else { c };
            aabbs.push(GpuAabb {
                min: [centre[0] - h[0], centre[1] - h[1], centre[2] - h[2], 0.0],
                max: [centre[0] + h[0], centre[1] + h[1], centre[2] + h[2], 0.0],
            });
            let is_static = if slab { i % 3 == 0 } else { i % 7 == 0 };
            shapes.push(GpuShape {
                hx: h[0],
                hy: h[1],
                hz: h[2],
                flags: if is_static { BODY_STATIC } else { 0 },
            });
        }
        (aabbs, shapes)
    }

    #[test]
    fn worlds_sorted_by_world_key_pair_exactly_within_each_world() {
        // 12 worlds of 120 random boxes each, all in the same 10 m cube (so boxes of different
        // worlds overlap everywhere), with a slab each; the sweep over the world-led keys (4
        // bits of world, so the bounds keep only 28 bits of their key) must give exactly the
        // pairs of brute force within each world, listed long boxes or not.
        let worlds = 12usize;
        let per = 120usize;
        let (mut aabbs, mut shapes) = (Vec::new(), Vec::new());
        let mut index = Vec::new();
        for w in 0..worlds {
            let (a, mut s) = boxes_with_slabs(100 + w as u64, per - 1, 1);
            for shape in &mut s {
                shape.flags |= (w as u32) << BODY_WORLD_SHIFT;
            }
            aabbs.extend(a);
            shapes.extend(s);
            index.extend(std::iter::repeat_n(w as u32, per));
        }
        let world_bits = u32::BITS - (worlds as u32 - 1).leading_zeros();
        let statics: Vec<bool> = shapes.iter().map(GpuShape::is_static).collect();
        let boxes: Vec<Aabb> = aabbs.iter().map(crate::kernels::aabb_from_gpu).collect();
        let all = tumble_broad::brute_force_pairs_filtered(&boxes, &statics).unwrap();
        let want: Vec<(u32, u32)> = all
            .iter()
            .copied()
            .filter(|&(a, b)| index[a as usize] == index[b as usize])
            .collect();
        // Pairs within worlds to find, and many more across worlds to leave out.
        assert!(want.len() > 100, "{} pairs", want.len());
        assert!(
            all.len() > 5 * want.len(),
            "{} pairs across worlds",
            all.len()
        );
        for (extent, axis) in [(2.0, 0), (2.0, 1), (1000.0, 2)] {
            let (keys, values) = write_sort_keys_in_worlds_cpu(&aabbs, &index, axis, world_bits);
            let (_, order) = radix_sort_cpu(&keys, &values, 32);
            let boxes = gather_sweep_boxes_cpu(&aabbs, &shapes, &order, axis);
            assert_eq!(
                split_sweep_pairs_in_worlds_cpu(&boxes, extent, world_bits),
                want,
                "axis {axis}, long extent {extent}"
            );
        }
    }

    #[test]
    fn bounds_closer_than_a_key_s_dropped_bits_do_not_pair() {
        // Two worlds (1 bit of world: each key drops the bound's lowest bit), each with a box
        // ending at x = 1 and one starting one ulp after it: equal keys, no overlap. Then
        // one starting at exactly 1: a touching pair, which closed intervals keep.
        let gap = f32::from_bits(1.0f32.to_bits() + 1);
        let mut aabbs = Vec::new();
        let mut shapes = Vec::new();
        let mut index = Vec::new();
        for w in 0..2u32 {
            let start = if w == 0 { gap } else { 1.0 };
            for (lo, hi) in [(0.0, 1.0), (start, 2.0)] {
                aabbs.push(GpuAabb {
                    min: [lo, 0.0, 0.0, 0.0],
                    max: [hi, 1.0, 1.0, 0.0],
                });
                shapes.push(GpuShape {
                    flags: w << BODY_WORLD_SHIFT,
                    ..Default::default()
                });
                index.push(w);
            }
        }
        assert_eq!(
            crate::kernels::write_sort_keys::sweep_key(0, 1.0, 1),
            crate::kernels::write_sort_keys::sweep_key(0, gap, 1),
            "the two bounds share a key"
        );
        let (keys, values) = write_sort_keys_in_worlds_cpu(&aabbs, &index, 0, 1);
        let (_, order) = radix_sort_cpu(&keys, &values, 32);
        let boxes = gather_sweep_boxes_cpu(&aabbs, &shapes, &order, 0);
        assert_eq!(
            split_sweep_pairs_in_worlds_cpu(&boxes, f32::INFINITY, 1),
            vec![(2, 3)]
        );
    }

    #[test]
    fn long_boxes_paired_apart_give_the_sweeps_pairs() {
        // An extent of 2 m makes the 8 m slabs long and no small box (1 m at most); 1000 m
        // makes none long. Few slabs (listed), and more than the list holds (swept).
        for (long, extent) in [(5, 2.0), (5, 1000.0), (MAX_LONG_BOXES as usize + 3, 2.0)] {
            let (aabbs, shapes) = boxes_with_slabs(long as u64, 400, long);
            for axis in 0..3 {
                let (keys, values) = write_sort_keys_cpu(&aabbs, axis);
                let (_, order) = radix_sort_cpu(&keys, &values, 32);
                let boxes = gather_sweep_boxes_cpu(&aabbs, &shapes, &order, axis);
                let want = sweep_pairs_cpu(&boxes);
                // Each slab crosses the cube, so it meets several boxes: pairs with a slab
                // are there to be found (more than 2 per slab on average).
                let with_slab = want.iter().filter(|&&(_, b)| b >= 400).count();
                assert!(with_slab > 2 * long, "{with_slab} pairs with a slab");
                assert_eq!(split_sweep_pairs_cpu(&boxes, extent), want, "axis {axis}");
            }
        }
    }

    #[test]
    fn the_long_extent_follows_the_median_body_not_the_floor() {
        // 99 unit cubes (diameter 2 sqrt 3 x 0.5 = 1.73 m) and a 100 m floor: the floor does
        // not move the median, so the extent is 16 x 1.73 m and the floor is past it.
        let cube = GpuShape {
            hx: 0.5,
            hy: 0.5,
            hz: 0.5,
            flags: 0,
        };
        let floor = GpuShape {
            hx: 50.0,
            hy: 0.5,
            hz: 50.0,
            flags: BODY_STATIC,
        };
        let mut shapes = vec![cube; 99];
        shapes.push(floor);
        let extent = long_extent(&shapes);
        assert!(
            (extent - LONG_BOX_FACTOR * 3f32.sqrt()).abs() < 1e-4,
            "{extent}"
        );
        assert!(100.0 > extent && extent > 2.0 * 3f32.sqrt());
        assert_eq!(long_extent(&[]), f32::INFINITY);
    }
}
