//! `store_impulses`: each constraint's final impulses back into its contact points, where the
//! next step's matching reads them for warm starting, and its tilt impulse into the tilt
//! buffer. The CPU twin is `ContactConstraint::store_impulses` (with `ContactCache::store` for
//! the tilt's normal in body A's frame).

use crate::kernel::{KernelArgs, KernelSpec};
use crate::shader::{Binding, ShaderSource, wgsl_file};

use super::shaders::CONTACT_COMMON;

/// Kernel: one thread per manifold.
pub static STORE_IMPULSES: KernelSpec = KernelSpec {
    name: "store_impulses",
    source: ShaderSource {
        common: CONTACT_COMMON,
        kernel: wgsl_file!("solver/store_impulses.wgsl"),
    },
    bindings: &[
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`STORE_IMPULSES`].
pub struct StoreImpulsesArgs<'a> {
    /// The contacts' `WorkList`.
    pub contact_work: &'a wgpu::Buffer,
    /// `array<GpuConstraint>`.
    pub constraints: &'a wgpu::Buffer,
    /// `array<GpuPose>` (still the start of the step).
    pub poses: &'a wgpu::Buffer,
    /// `array<GpuContact>` (points), impulses updated.
    pub contacts: &'a wgpu::Buffer,
    /// Output `array<GpuTilt>` for the next step.
    pub tilts: &'a wgpu::Buffer,
}

impl KernelArgs for StoreImpulsesArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.contact_work,
            self.constraints,
            self.poses,
            self.contacts,
            self.tilts,
        ]
    }
}
