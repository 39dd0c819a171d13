//! `kinematic_wake`: moving kinematic bodies wake the sleeping islands their AABBs reach (the
//! broad phase pairs neither with the other). The CPU twin is
//! [`super::cpu::SleepCpu::kinematic_wake`].

use crate::kernel::{KernelArgs, KernelSpec};
use crate::shader::{Binding, ShaderSource, wgsl_file};

use super::shaders::SLEEP_COMMON;

/// Kernel: one thread per body, looping over the kinematic bodies.
pub static KINEMATIC_WAKE: KernelSpec = KernelSpec {
    name: "kinematic_wake",
    source: ShaderSource {
        common: SLEEP_COMMON,
        kernel: wgsl_file!("sleep/kinematic_wake.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`KINEMATIC_WAKE`].
pub struct KinematicWakeArgs<'a> {
    /// `SleepParams`.
    pub params: &'a wgpu::Buffer,
    /// `array<u32>`: the kinematic bodies.
    pub kinematic: &'a wgpu::Buffer,
    /// `array<GpuVelocity>`: the step's velocities.
    pub velocities: &'a wgpu::Buffer,
    /// `array<GpuAabb>`: the step's AABBs.
    pub aabbs: &'a wgpu::Buffer,
    /// `array<u32>`: island labels.
    pub island: &'a wgpu::Buffer,
    /// `array<atomic<u32>>`: wake flags by island label, set.
    pub wake: &'a wgpu::Buffer,
}

impl KernelArgs for KinematicWakeArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.kinematic,
            self.velocities,
            self.aabbs,
            self.island,
            self.wake,
        ]
    }
}
