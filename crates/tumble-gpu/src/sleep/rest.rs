//! Rest times and falling asleep: `update_rest` (rest timers, and each body its own island),
//! `island_rest` (each island's shortest rest time), `fall_asleep` (islands that rested long
//! enough leave the step). Their CPU twins are the methods of [`super::cpu::SleepCpu`] of the
//! same names.

use crate::kernel::{KernelArgs, KernelSpec};
use crate::shader::{Binding, ShaderSource, wgsl_file};

use super::shaders::SLEEP_COMMON;

/// Kernel: one thread per body.
pub static UPDATE_REST: KernelSpec = KernelSpec {
    name: "update_rest",
    source: ShaderSource {
        common: SLEEP_COMMON,
        kernel: wgsl_file!("sleep/update_rest.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`UPDATE_REST`].
pub struct UpdateRestArgs<'a> {
    /// `SleepParams`.
    pub params: &'a wgpu::Buffer,
    /// `array<GpuBody>`: every body as uploaded (its real kind).
    pub awake_bodies: &'a wgpu::Buffer,
    /// `array<GpuVelocity>`: the step's final velocities.
    pub velocities: &'a wgpu::Buffer,
    /// `array<u32>`: island labels.
    pub island: &'a wgpu::Buffer,
    /// `array<f32>`: rest times, updated.
    pub rest_time: &'a wgpu::Buffer,
    /// `array<u32>`: search labels, each body its own.
    pub labels: &'a wgpu::Buffer,
    /// `array<u32>`: the first round's copy of them.
    pub next_labels: &'a wgpu::Buffer,
    /// `array<u32>`: shortest rest time bits by label, reset to `REST_UNSET`.
    pub shortest_rest: &'a wgpu::Buffer,
    /// One `atomic<u32>`: bodies whose rest reached `TIME_TO_SLEEP`, counted up.
    pub ready: &'a wgpu::Buffer,
}

impl KernelArgs for UpdateRestArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.awake_bodies,
            self.velocities,
            self.island,
            self.rest_time,
            self.labels,
            self.next_labels,
            self.shortest_rest,
            self.ready,
        ]
    }
}

/// Kernel: one thread per body.
pub static ISLAND_REST: KernelSpec = KernelSpec {
    name: "island_rest",
    source: ShaderSource {
        common: SLEEP_COMMON,
        kernel: wgsl_file!("sleep/island_rest.wgsl"),
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

/// Buffers of [`ISLAND_REST`].
pub struct IslandRestArgs<'a> {
    /// `SleepParams`.
    pub params: &'a wgpu::Buffer,
    /// `array<GpuBody>`: every body as uploaded.
    pub awake_bodies: &'a wgpu::Buffer,
    /// `array<u32>`: island labels.
    pub island: &'a wgpu::Buffer,
    /// `array<u32>`: the finished search labels.
    pub labels: &'a wgpu::Buffer,
    /// `array<f32>`: rest times.
    pub rest_time: &'a wgpu::Buffer,
    /// `array<atomic<u32>>`: shortest rest time bits by label, lowered.
    pub shortest_rest: &'a wgpu::Buffer,
}

impl KernelArgs for IslandRestArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.awake_bodies,
            self.island,
            self.labels,
            self.rest_time,
            self.shortest_rest,
        ]
    }
}

/// Kernel: one thread per body.
pub static FALL_ASLEEP: KernelSpec = KernelSpec {
    name: "fall_asleep",
    source: ShaderSource {
        common: SLEEP_COMMON,
        kernel: wgsl_file!("sleep/fall_asleep.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`FALL_ASLEEP`].
pub struct FallAsleepArgs<'a> {
    /// `SleepParams`.
    pub params: &'a wgpu::Buffer,
    /// `array<u32>`, one entry: nonzero when the island search did not finish.
    pub unfinished: &'a wgpu::Buffer,
    /// `array<GpuBody>`: every body as uploaded.
    pub awake_bodies: &'a wgpu::Buffer,
    /// `array<u32>`: the finished search labels.
    pub labels: &'a wgpu::Buffer,
    /// `array<u32>`: shortest rest time bits by label.
    pub shortest_rest: &'a wgpu::Buffer,
    /// `array<u32>`: island labels, set for the bodies falling asleep.
    pub island: &'a wgpu::Buffer,
    /// `array<GpuVelocity>`: zeroed for the bodies falling asleep.
    pub velocities: &'a wgpu::Buffer,
    /// `array<GpuBody>`: the solver's bodies, made fixed for the bodies falling asleep.
    pub bodies: &'a wgpu::Buffer,
    /// `array<GpuShape>`: the collision shapes, flagged static for the bodies falling asleep.
    pub shapes: &'a wgpu::Buffer,
}

impl KernelArgs for FallAsleepArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.unfinished,
            self.awake_bodies,
            self.labels,
            self.shortest_rest,
            self.island,
            self.velocities,
            self.bodies,
            self.shapes,
        ]
    }
}
