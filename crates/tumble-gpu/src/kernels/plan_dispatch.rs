//! `plan_dispatch`: an append counter -> a `WorkList` (clamped count, raw count, indirect
//! dispatch size), so a count produced on the GPU sizes later dispatches without a readback.

use crate::kernel::{KernelArgs, KernelSpec};
use crate::layout::WorkList;
use crate::shader::{Binding, ShaderSource, common, wgsl_file};

/// The kernel: a single thread.
pub static PLAN_DISPATCH: KernelSpec = KernelSpec {
    name: "plan_dispatch",
    source: ShaderSource {
        common: &[common::CONSTANTS, common::LAYOUT],
        kernel: wgsl_file!("plan_dispatch.wgsl"),
    },
    bindings: &[Binding::StorageRead, Binding::StorageReadWrite],
};

/// Buffers of [`PLAN_DISPATCH`].
pub struct PlanDispatchArgs<'a> {
    /// The append counter (`u32` at offset 0).
    pub counter: &'a wgpu::Buffer,
    /// The `WorkList` to fill; its `capacity` is set by the host when the list is allocated.
    pub work: &'a wgpu::Buffer,
}

impl KernelArgs for PlanDispatchArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![self.counter, self.work]
    }
}

/// The CPU twin of [`PLAN_DISPATCH`].
pub fn plan_dispatch_cpu(requested: u32, capacity: u32) -> WorkList {
    let mut work = WorkList::for_count(requested.min(capacity));
    work.requested = requested;
    work.capacity = capacity;
    work
}
