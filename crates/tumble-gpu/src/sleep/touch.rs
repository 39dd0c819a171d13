//! `touch_sleepers`: the step's manifolds wake the sleeping islands awake bodies reached, and
//! moving kinematic bodies keep what they touch from resting. The CPU twin is
//! [`tumble_solver::SleepLabels::touch_sleepers`].

use crate::kernel::kernel;

kernel! {
    /// Buffers of [`TOUCH_SLEEPERS`].
    pub struct TouchSleepersArgs {
        /// The step's pair `WorkList`.
        work,
        /// `array<GpuManifold>`: the step's manifolds.
        manifolds,
        /// `array<GpuBody>`: every body as uploaded.
        awake_bodies,
        /// `array<GpuVelocity>`: the step's final velocities.
        velocities,
        /// `array<u32>`: island labels.
        island,
        /// `array<f32>`: rest times, reset next to moving kinematic bodies.
        rest_time,
        /// `array<atomic<u32>>`: wake flags by island label, set.
        wake,
    }
    /// Kernel: one thread per manifold (dispatched indirectly from the pair work list).
    pub static TOUCH_SLEEPERS = "sleep/touch_sleepers.wgsl";
}
