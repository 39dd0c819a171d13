//! `gather_sweep_boxes`: AABBs copied into sweep order, sweep axis first, with index and flags.

use crate::kernel::KernelSpec;
use crate::layout::{GpuAabb, GpuShape, GpuSweepBox};
use crate::shader::file;

/// The kernel: one thread per sorted position.
pub static GATHER_SWEEP_BOXES: KernelSpec = KernelSpec::new(file("gather_sweep_boxes.wgsl"));

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
