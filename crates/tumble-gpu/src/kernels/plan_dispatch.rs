//! `plan_dispatch`: an append counter -> a `WorkList` (clamped count, raw count, indirect
//! dispatch size), so a count produced on the GPU sizes later dispatches without a readback.

use crate::kernel::KernelSpec;
use crate::layout::WorkList;
use crate::shader::file;

/// The kernel: a single thread.
pub static PLAN_DISPATCH: KernelSpec = KernelSpec::new(file("plan_dispatch.wgsl"));

/// The CPU twin of [`PLAN_DISPATCH`].
pub fn plan_dispatch_cpu(requested: u32, capacity: u32) -> WorkList {
    let mut work = WorkList::for_count(requested.min(capacity));
    work.requested = requested;
    work.capacity = capacity;
    work
}
