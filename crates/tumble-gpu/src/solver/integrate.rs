//! The per-body kernels of the solve and finish stages: `integrate_velocities`,
//! `integrate_positions` and `finalize_bodies`. Their CPU twins are tumble-solver's
//! `integrate_velocities`, `integrate_positions` and `finalize_bodies`, which the GPU
//! versus CPU tests run on the same bodies.

use crate::kernel::{KernelArgs, KernelSpec};
use crate::shader::{Binding, ShaderSource, wgsl_file};

use super::shaders::BODY_COMMON;

/// Kernel: one thread per body, velocities by one substep.
pub static INTEGRATE_VELOCITIES: KernelSpec = KernelSpec {
    name: "integrate_velocities",
    source: ShaderSource {
        common: BODY_COMMON,
        kernel: wgsl_file!("solver/integrate_velocities.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// Kernel: one thread per body, deltas by one substep.
pub static INTEGRATE_POSITIONS: KernelSpec = KernelSpec {
    name: "integrate_positions",
    source: ShaderSource {
        common: BODY_COMMON,
        kernel: wgsl_file!("solver/integrate_positions.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Kernel: one thread per body, deltas into poses.
pub static FINALIZE_BODIES: KernelSpec = KernelSpec {
    name: "finalize_bodies",
    source: ShaderSource {
        common: BODY_COMMON,
        kernel: wgsl_file!("solver/finalize_bodies.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`INTEGRATE_VELOCITIES`].
pub struct IntegrateVelocitiesArgs<'a> {
    /// `SolverParams`.
    pub params: &'a wgpu::Buffer,
    /// `array<GpuBody>`.
    pub bodies: &'a wgpu::Buffer,
    /// `array<GpuPose>` (start of step).
    pub poses: &'a wgpu::Buffer,
    /// `array<GpuSolverBody>` (for the delta rotation).
    pub solver_bodies: &'a wgpu::Buffer,
    /// `array<GpuVelocity>`, updated.
    pub velocities: &'a wgpu::Buffer,
}

impl KernelArgs for IntegrateVelocitiesArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.bodies,
            self.poses,
            self.solver_bodies,
            self.velocities,
        ]
    }
}

/// Buffers of [`INTEGRATE_POSITIONS`].
pub struct IntegratePositionsArgs<'a> {
    /// `SolverParams`.
    pub params: &'a wgpu::Buffer,
    /// `array<GpuBody>`.
    pub bodies: &'a wgpu::Buffer,
    /// `array<GpuPose>` (start of step, for the gyroscopic half step).
    pub poses: &'a wgpu::Buffer,
    /// `array<GpuVelocity>` (clamped, and turned by the gyroscopic half step, in place).
    pub velocities: &'a wgpu::Buffer,
    /// `array<GpuSolverBody>`, deltas updated.
    pub solver_bodies: &'a wgpu::Buffer,
}

impl KernelArgs for IntegratePositionsArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.bodies,
            self.poses,
            self.velocities,
            self.solver_bodies,
        ]
    }
}

/// Buffers of [`FINALIZE_BODIES`].
pub struct FinalizeBodiesArgs<'a> {
    /// `SolverParams`.
    pub params: &'a wgpu::Buffer,
    /// `array<GpuBody>`.
    pub bodies: &'a wgpu::Buffer,
    /// `array<GpuSolverBody>`.
    pub solver_bodies: &'a wgpu::Buffer,
    /// `array<GpuPose>`, updated.
    pub poses: &'a wgpu::Buffer,
}

impl KernelArgs for FinalizeBodiesArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![self.params, self.bodies, self.solver_bodies, self.poses]
    }
}
