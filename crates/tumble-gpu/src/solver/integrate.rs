//! The per-body kernels of the solve and finish stages: `integrate_velocities`,
//! `integrate_positions` and `finalize_bodies`. Their CPU twins are tumble-solver's
//! `integrate_velocities`, `integrate_positions` and `finalize_bodies`, which the GPU
//! versus CPU tests run on the same bodies.

use crate::kernel::kernel;

kernel! {
    /// Buffers of [`INTEGRATE_VELOCITIES`].
    pub struct IntegrateVelocitiesArgs {
        /// `SolverParams`.
        params,
        /// `array<GpuBody>`.
        bodies,
        /// `array<GpuPose>` (start of step).
        poses,
        /// `array<GpuSolverBody>` (for the delta rotation).
        solver_bodies,
        /// `array<GpuVelocity>`, updated.
        velocities,
    }
    /// Kernel: one thread per body, velocities by one substep.
    pub static INTEGRATE_VELOCITIES = "solver/integrate_velocities.wgsl";
}

kernel! {
    /// Buffers of [`INTEGRATE_POSITIONS`].
    pub struct IntegratePositionsArgs {
        /// `SolverParams`.
        params,
        /// `array<GpuBody>`.
        bodies,
        /// `array<GpuPose>` (start of step, for the gyroscopic half step).
        poses,
        /// `array<GpuVelocity>` (clamped, and turned by the gyroscopic half step, in place).
        velocities,
        /// `array<GpuSolverBody>`, deltas updated.
        solver_bodies,
    }
    /// Kernel: one thread per body, deltas by one substep.
    pub static INTEGRATE_POSITIONS = "solver/integrate_positions.wgsl";
}

kernel! {
    /// Buffers of [`FINALIZE_BODIES`].
    pub struct FinalizeBodiesArgs {
        /// `SolverParams`.
        params,
        /// `array<GpuBody>`.
        bodies,
        /// `array<GpuSolverBody>`.
        solver_bodies,
        /// `array<GpuPose>`, updated.
        poses,
    }
    /// Kernel: one thread per body, deltas into poses.
    pub static FINALIZE_BODIES = "solver/finalize_bodies.wgsl";
}
