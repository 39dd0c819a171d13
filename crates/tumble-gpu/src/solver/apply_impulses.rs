//! `apply_impulses`: impulses the host queued between steps, applied on the GPU at the start
//! of the next step (so applying one needs no readback). The CPU twin is the facade's
//! `World::apply_impulse` arithmetic (`velocities_after_impulse` in `tumble`).

use crate::kernel::KernelSpec;
use crate::shader::file;

/// Kernel: a single thread, impulses in queue order.
pub static APPLY_IMPULSES: KernelSpec = KernelSpec::new(file("solver/apply_impulses.wgsl"));
