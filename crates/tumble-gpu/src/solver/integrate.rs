//! The per-body kernels of the solve and finish stages: `integrate_velocities`,
//! `integrate_positions` and `finalize_bodies`. Their CPU twins are tumble-solver's
//! `integrate_velocities`, `integrate_positions` and `finalize_bodies`, which the GPU
//! versus CPU tests run on the same bodies.

use crate::kernel::KernelSpec;
use crate::shader::file;

/// Kernel: one thread per body, velocities by one substep.
pub static INTEGRATE_VELOCITIES: KernelSpec =
    KernelSpec::new(file("solver/integrate_velocities.wgsl"));

/// Kernel: one thread per body, deltas by one substep.
pub static INTEGRATE_POSITIONS: KernelSpec =
    KernelSpec::new(file("solver/integrate_positions.wgsl"));

/// Kernel: one thread per body, deltas into poses.
pub static FINALIZE_BODIES: KernelSpec = KernelSpec::new(file("solver/finalize_bodies.wgsl"));
