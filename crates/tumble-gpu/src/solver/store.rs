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
        /// Manifold indices by color: the manifold of each constraint slot.
        color_order,
        /// The constraint store (`GpuConstraint` rows, by slot).
        constraints,
        /// `array<GpuPose>` (still the start of the step).
        poses,
        /// `array<GpuContact>` (points), impulses updated.
        contacts,
        /// Output `array<GpuTilt>` for the next step.
        tilts,
    }
    /// Kernel: one thread per constraint slot.
    pub static STORE_IMPULSES = "solver/store_impulses.wgsl";
}
