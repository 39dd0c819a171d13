//! `touch_sleepers`: the step's manifolds wake the sleeping islands awake bodies reached, and
//! moving kinematic bodies keep what they touch from resting. The CPU twin is
//! [`super::cpu::SleepCpu::touch_sleepers`].

use crate::kernel::{KernelArgs, KernelSpec};
use crate::shader::{Binding, ShaderSource, wgsl_file};

use super::shaders::SLEEP_COMMON;

/// Kernel: one thread per manifold (dispatched indirectly from the pair work list).
pub static TOUCH_SLEEPERS: KernelSpec = KernelSpec {
    name: "touch_sleepers",
    source: ShaderSource {
        common: SLEEP_COMMON,
        kernel: wgsl_file!("sleep/touch_sleepers.wgsl"),
    },
    bindings: &[
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`TOUCH_SLEEPERS`].
pub struct TouchSleepersArgs<'a> {
    /// The step's pair `WorkList`.
    pub work: &'a wgpu::Buffer,
    /// `array<GpuManifold>`: the step's manifolds.
    pub manifolds: &'a wgpu::Buffer,
    /// `array<GpuBody>`: every body as uploaded.
    pub awake_bodies: &'a wgpu::Buffer,
    /// `array<GpuVelocity>`: the step's final velocities.
    pub velocities: &'a wgpu::Buffer,
    /// `array<u32>`: island labels.
    pub island: &'a wgpu::Buffer,
    /// `array<f32>`: rest times, reset next to moving kinematic bodies.
    pub rest_time: &'a wgpu::Buffer,
    /// `array<atomic<u32>>`: wake flags by island label, set.
    pub wake: &'a wgpu::Buffer,
}

impl KernelArgs for TouchSleepersArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.work,
            self.manifolds,
            self.awake_bodies,
            self.velocities,
            self.island,
            self.rest_time,
            self.wake,
        ]
    }
}
