//! `sweep_pairs`: the sweep of sweep-and-prune over bodies sorted by AABB lower bound.

use crate::kernel::{KernelArgs, KernelSpec};
use crate::layout::{BODY_STATIC, GpuSweepBox};
use crate::shader::{Binding, ShaderSource, common, wgsl_file};

/// The kernel: one thread per sorted body, appending pairs through an atomic counter.
pub static SWEEP_PAIRS: KernelSpec = KernelSpec {
    name: "sweep_pairs",
    source: ShaderSource {
        common: &[common::CONSTANTS, common::INDEXING, common::LAYOUT],
        kernel: wgsl_file!("sweep_pairs.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`SWEEP_PAIRS`].
pub struct SweepPairsArgs<'a> {
    /// [`crate::layout::SweepParams`].
    pub params: &'a wgpu::Buffer,
    /// `array<GpuSweepBox>` in sweep order, from `gather_sweep_boxes`.
    pub sweep_boxes: &'a wgpu::Buffer,
    /// Append counter (`u32`, cleared before the sweep).
    pub counter: &'a wgpu::Buffer,
    /// Output: smaller body index of each pair.
    pub pair_a: &'a wgpu::Buffer,
    /// Output: larger body index of each pair.
    pub pair_b: &'a wgpu::Buffer,
}

impl KernelArgs for SweepPairsArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.sweep_boxes,
            self.counter,
            self.pair_a,
            self.pair_b,
        ]
    }
}

/// The CPU twin of [`SWEEP_PAIRS`] followed by the canonical sort: every overlapping pair
/// that is not static-static, as `(smaller, larger)`, ascending, from the boxes in sweep
/// order (closed intervals; the sweep axis is implied by the order).
pub fn sweep_pairs_cpu(boxes: &[GpuSweepBox]) -> Vec<(u32, u32)> {
    let mut pairs = Vec::new();
    for (p, me) in boxes.iter().enumerate() {
        for other in &boxes[p + 1..] {
            if other.lo_0 > me.hi_0 {
                break;
            }
            let overlaps = other.lo_1 <= me.hi_1
                && me.lo_1 <= other.hi_1
                && other.lo_2 <= me.hi_2
                && me.lo_2 <= other.hi_2;
            let both_static = me.flags & other.flags & BODY_STATIC != 0;
            if overlaps && !both_static {
                pairs.push((me.body.min(other.body), me.body.max(other.body)));
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
    use crate::kernels::write_sort_keys::write_sort_keys_cpu;
    use crate::layout::{GpuAabb, GpuShape};
    use rand::{Rng, SeedableRng};
    use tumble_geometry::{Aabb, Point3};

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
        let boxes: Vec<Aabb> = aabbs
            .iter()
            .map(|b| {
                Aabb::new(
                    Point3::new(b.min[0], b.min[1], b.min[2]),
                    Point3::new(b.max[0], b.max[1], b.max[2]),
                )
            })
            .collect();
        let want = tumble_broad::brute_force_pairs_filtered(&boxes, &statics).unwrap();
        assert!(want.len() > n / 2, "a scene with pairs");
        for axis in 0..3 {
            let (keys, values) = write_sort_keys_cpu(&aabbs, axis);
            let (_, order) = radix_sort_cpu(&keys, &values, 32);
            let boxes = gather_sweep_boxes_cpu(&aabbs, &shapes, &order, axis);
            assert_eq!(sweep_pairs_cpu(&boxes), want);
        }
    }
}
