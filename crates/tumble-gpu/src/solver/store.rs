//! `store_impulses`: each constraint's final impulses back into its contact points, where the
//! next step's matching reads them for warm starting, and its tilt impulse into the tilt
//! buffer. The CPU twin is `ContactConstraint::store_impulses` (with `ContactCache::store` for
//! the tilt's normal in body A's frame).

use crate::kernel::kernel;

kernel! {
    /// Buffers of [`STORE_IMPULSES`].
    pub struct StoreImpulsesArgs {
        /// The contacts' `WorkList`.
        contact_work,
        /// `array<GpuConstraint>`.
        constraints,
        /// `array<GpuPose>` (still the start of the step).
        poses,
        /// `array<GpuContact>` (points), impulses updated.
        contacts,
        /// Output `array<GpuTilt>` for the next step.
        tilts,
    }
    /// Kernel: one thread per manifold.
    pub static STORE_IMPULSES = "solver/store_impulses.wgsl";
}
