//! `sweep_pairs`: the sweep of sweep-and-prune over bodies sorted by AABB lower bound.

use crate::kernel::{KernelArgs, KernelSpec};
use crate::layout::{BODY_STATIC, GpuAabb, GpuShape};
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
        Binding::StorageRead,
        Binding::StorageRead,
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
    /// `SweepAxis` from `choose_axis`.
    pub sweep_axis: &'a wgpu::Buffer,
    /// `array<GpuAabb>`.
    pub aabbs: &'a wgpu::Buffer,
    /// `array<GpuShape>` (for the static flag).
    pub shapes: &'a wgpu::Buffer,
    /// Body indices in sorted order of AABB lower bound.
    pub sorted_bodies: &'a wgpu::Buffer,
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
            self.sweep_axis,
            self.aabbs,
            self.shapes,
            self.sorted_bodies,
            self.counter,
            self.pair_a,
            self.pair_b,
        ]
    }
}

/// True when the boxes overlap or touch on all three axes (closed intervals).
fn overlaps(a: &GpuAabb, b: &GpuAabb) -> bool {
    (0..3).all(|k| a.min[k] <= b.max[k] && b.min[k] <= a.max[k])
}

/// The CPU twin of [`SWEEP_PAIRS`] followed by the canonical sort: every overlapping pair
/// that is not static-static, as `(smaller, larger)`, ascending. `sorted_bodies` is the
/// sweep order (body indices sorted by lower bound along `axis`).
pub fn sweep_pairs_cpu(
    aabbs: &[GpuAabb],
    shapes: &[GpuShape],
    sorted_bodies: &[u32],
    axis: u32,
) -> Vec<(u32, u32)> {
    let axis = axis as usize;
    let is_static = |i: u32| shapes[i as usize].flags & BODY_STATIC != 0;
    let mut pairs = Vec::new();
    for (p, &i) in sorted_bodies.iter().enumerate() {
        let a = &aabbs[i as usize];
        for &j in &sorted_bodies[p + 1..] {
            let b = &aabbs[j as usize];
            if b.min[axis] > a.max[axis] {
                break;
            }
            if (is_static(i) && is_static(j)) || !overlaps(a, b) {
                continue;
            }
            pairs.push((i.min(j), i.max(j)));
        }
    }
    pairs.sort_unstable();
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernels::radix_sort::radix_sort_cpu;
    use crate::kernels::write_sort_keys::write_sort_keys_cpu;
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
            assert_eq!(sweep_pairs_cpu(&aabbs, &shapes, &order, axis), want);
        }
    }
}
