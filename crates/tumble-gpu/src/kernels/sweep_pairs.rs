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
