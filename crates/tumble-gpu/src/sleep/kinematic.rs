//! `kinematic_wake`: moving kinematic bodies wake the sleeping islands their AABBs reach (the
//! broad phase pairs neither with the other). The CPU twin is
//! [`tumble_solver::SleepLabels::kinematic_wake`].

use crate::kernel::kernel;

kernel! {
    /// Buffers of [`KINEMATIC_WAKE`].
    pub struct KinematicWakeArgs {
        /// `SleepParams`.
        params,
        /// `array<u32>`: the kinematic bodies.
        kinematic,
        /// `array<GpuVelocity>`: the step's velocities.
        velocities,
        /// `array<GpuAabb>`: the step's AABBs.
        aabbs,
        /// `array<u32>`: island labels.
        island,
        /// `array<atomic<u32>>`: wake flags by island label, set.
        wake,
    }
    /// Kernel: one thread per body, looping over the kinematic bodies.
    pub static KINEMATIC_WAKE = "sleep/kinematic_wake.wgsl";
}
