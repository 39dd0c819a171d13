//! Waking: `wake_bodies` flags the islands of the bodies the host touched, `wake_islands`
//! wakes every body of a flagged island at the start of a step and counts the bodies the
//! step moves. Their CPU twins are
//! [`super::cpu::SleepCpu::wake_bodies`] and [`super::cpu::SleepCpu::wake_islands`].

use crate::kernel::{KernelArgs, KernelSpec};
use crate::shader::{Binding, ShaderSource, wgsl_file};

use super::shaders::SLEEP_COMMON;

/// Kernel: a single thread, queued bodies in order.
pub static WAKE_BODIES: KernelSpec = KernelSpec {
    name: "wake_bodies",
    source: ShaderSource {
        common: SLEEP_COMMON,
        kernel: wgsl_file!("sleep/wake_bodies.wgsl"),
    },
    bindings: &[
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`WAKE_BODIES`].
pub struct WakeBodiesArgs<'a> {
    /// `array<u32>`: the bodies touched by the host since the last step.
    pub queued: &'a wgpu::Buffer,
    /// `array<u32>`: each body's island label, or `AWAKE`.
    pub island: &'a wgpu::Buffer,
    /// `array<f32>`: rest times, reset for the queued bodies.
    pub rest_time: &'a wgpu::Buffer,
    /// `array<u32>`: wake flags by island label, set.
    pub wake: &'a wgpu::Buffer,
}

impl KernelArgs for WakeBodiesArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![self.queued, self.island, self.rest_time, self.wake]
    }
}

/// Kernel: one thread per body.
pub static WAKE_ISLANDS: KernelSpec = KernelSpec {
    name: "wake_islands",
    source: ShaderSource {
        common: SLEEP_COMMON,
        kernel: wgsl_file!("sleep/wake_islands.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`WAKE_ISLANDS`].
pub struct WakeIslandsArgs<'a> {
    /// `SleepParams`.
    pub params: &'a wgpu::Buffer,
    /// `array<u32>`: wake flags by island label.
    pub wake: &'a wgpu::Buffer,
    /// `array<GpuBody>`: every body as uploaded (awake).
    pub awake_bodies: &'a wgpu::Buffer,
    /// `array<u32>`: island labels, `AWAKE` for the bodies woken.
    pub island: &'a wgpu::Buffer,
    /// `array<f32>`: rest times, reset for the bodies woken.
    pub rest_time: &'a wgpu::Buffer,
    /// `array<GpuBody>`: the solver's bodies, restored for the bodies woken.
    pub bodies: &'a wgpu::Buffer,
    /// `array<GpuShape>`: the collision shapes, static flag cleared for the bodies woken.
    pub shapes: &'a wgpu::Buffer,
    /// One `u32`, cleared before: the bodies the step moves (not fixed once woken) are
    /// added to it.
    pub active: &'a wgpu::Buffer,
}

impl KernelArgs for WakeIslandsArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.wake,
            self.awake_bodies,
            self.island,
            self.rest_time,
            self.bodies,
            self.shapes,
            self.active,
        ]
    }
}
