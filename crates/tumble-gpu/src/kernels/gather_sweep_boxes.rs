//! `gather_sweep_boxes`: AABBs copied into sweep order, sweep axis first, with index and flags.

use crate::kernel::{KernelArgs, KernelSpec};
use crate::layout::{GpuAabb, GpuShape, GpuSweepBox};
use crate::shader::{Binding, ShaderSource, common, wgsl_file};

/// The kernel: one thread per sorted position.
pub static GATHER_SWEEP_BOXES: KernelSpec = KernelSpec {
    name: "gather_sweep_boxes",
    source: ShaderSource {
        common: &[
            common::CONSTANTS,
            common::INDEXING,
            common::LAYOUT,
            common::SWEEP,
        ],
        kernel: wgsl_file!("gather_sweep_boxes.wgsl"),
    },
    bindings: &[
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::Uniform,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`GATHER_SWEEP_BOXES`].
pub struct GatherSweepBoxesArgs<'a> {
    /// The bodies' `WorkList`.
    pub bodies: &'a wgpu::Buffer,
    /// `SweepAxis` from `choose_axis`.
    pub sweep_axis: &'a wgpu::Buffer,
    /// `array<GpuAabb>`.
    pub aabbs: &'a wgpu::Buffer,
    /// `array<GpuShape>` (for the flags).
    pub shapes: &'a wgpu::Buffer,
    /// Body indices sorted by lower bound on the sweep axis.
    pub sorted_bodies: &'a wgpu::Buffer,
    /// Output `array<GpuSweepBox>`, one per sorted position.
    pub sweep_boxes: &'a wgpu::Buffer,
    /// [`crate::layout::SweepParams`] (the long extent).
    pub params: &'a wgpu::Buffer,
    /// Output: the long box count and list (cleared count before).
    pub long_boxes: &'a wgpu::Buffer,
}

impl KernelArgs for GatherSweepBoxesArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.bodies,
            self.sweep_axis,
            self.aabbs,
            self.shapes,
            self.sorted_bodies,
            self.sweep_boxes,
            self.params,
            self.long_boxes,
        ]
    }
}

/// The CPU twin of [`GATHER_SWEEP_BOXES`].
pub fn gather_sweep_boxes_cpu(
    aabbs: &[GpuAabb],
    shapes: &[GpuShape],
    sorted_bodies: &[u32],
    axis: u32,
) -> Vec<GpuSweepBox> {
    let a = [axis, (axis + 1) % 3, (axis + 2) % 3].map(|k| k as usize);
    sorted_bodies
        .iter()
        .map(|&i| {
            let b = &aabbs[i as usize];
            GpuSweepBox {
                lo_0: b.min[a[0]],
                lo_1: b.min[a[1]],
                lo_2: b.min[a[2]],
                body: i,
                hi_0: b.max[a[0]],
                hi_1: b.max[a[1]],
                hi_2: b.max[a[2]],
                flags: shapes[i as usize].flags,
            }
        })
        .collect()
}
