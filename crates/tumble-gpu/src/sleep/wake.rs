//! Waking: `wake_bodies` flags the islands of the bodies the host touched, `wake_islands`
//! wakes every body of a flagged island at the start of a step and counts the bodies the
//! step moves. Their CPU twins are
//! [`tumble_solver::SleepLabels::wake_bodies`] and [`tumble_solver::SleepLabels::wake_islands`].

use crate::kernel::kernel;

kernel! {
    /// Buffers of [`WAKE_BODIES`].
    pub struct WakeBodiesArgs {
        /// `array<u32>`: the bodies touched by the host since the last step.
        queued,
        /// `array<u32>`: each body's island label, or `AWAKE`.
        island,
        /// `array<f32>`: rest times, reset for the queued bodies.
        rest_time,
        /// `array<u32>`: wake flags by island label, set.
        wake,
    }
    /// Kernel: a single thread, queued bodies in order.
    pub static WAKE_BODIES = "sleep/wake_bodies.wgsl";
}

kernel! {
    /// Buffers of [`WAKE_ISLANDS`].
    pub struct WakeIslandsArgs {
        /// `SleepParams`.
        params,
        /// `array<u32>`: wake flags by island label.
        wake,
        /// `array<GpuBody>`: every body as uploaded (awake).
        awake_bodies,
        /// `array<u32>`: island labels, `AWAKE` for the bodies woken.
        island,
        /// `array<f32>`: rest times, reset for the bodies woken.
        rest_time,
        /// `array<GpuBody>`: the solver's bodies, restored for the bodies woken.
        bodies,
        /// `array<GpuShape>`: the collision shapes, static flag cleared for the bodies woken.
        shapes,
        /// One `u32`, cleared before: the bodies the step moves (not fixed once woken) are
        /// added to it.
        moving,
    }
    /// Kernel: one thread per body.
    pub static WAKE_ISLANDS = "sleep/wake_islands.wgsl";
}
