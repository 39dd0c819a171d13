//! `solve_fused`: the color and solve stages in one workgroup and one dispatch, for scenes
//! small enough that per-dispatch overhead dominates. It computes exactly what the wide path
//! computes (same functions, same order), so the choice between them never changes a result.

use crate::kernel::{KernelArgs, KernelSpec};
use crate::shader::{Binding, ShaderSource, wgsl_file};

use super::shaders::FUSED_COMMON;

/// Kernel: a single workgroup.
pub static SOLVE_FUSED: KernelSpec = KernelSpec {
    name: "solve_fused",
    source: ShaderSource {
        common: FUSED_COMMON,
        kernel: wgsl_file!("solver/solve_fused.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`SOLVE_FUSED`].
pub struct SolveFusedArgs<'a> {
    /// `SolverParams`.
    pub params: &'a wgpu::Buffer,
    /// The contacts' `WorkList`.
    pub contact_work: &'a wgpu::Buffer,
    /// `array<GpuManifold>`.
    pub manifolds: &'a wgpu::Buffer,
    /// `array<GpuContact>` (points), impulses updated.
    pub contacts: &'a wgpu::Buffer,
    /// `array<GpuBody>`.
    pub bodies: &'a wgpu::Buffer,
    /// Last step's `array<ColorSlot>`.
    pub previous_colors: &'a wgpu::Buffer,
    /// This step's `array<ColorSlot>`.
    pub color_state: &'a wgpu::Buffer,
    /// Used-color masks and claims.
    pub color_marks: &'a wgpu::Buffer,
    /// Undecided lists.
    pub color_scratch: &'a wgpu::Buffer,
    /// Per-color offsets.
    pub color_offsets: &'a wgpu::Buffer,
    /// Constraint order by color.
    pub color_order: &'a wgpu::Buffer,
    /// `array<GpuPose>`, updated.
    pub poses: &'a wgpu::Buffer,
    /// `array<GpuVelocity>`, updated.
    pub velocities: &'a wgpu::Buffer,
    /// `array<GpuSolverBody>`.
    pub solver_bodies: &'a wgpu::Buffer,
    /// `array<GpuConstraint>`.
    pub constraints: &'a wgpu::Buffer,
    /// Last step's `array<GpuTilt>`.
    pub previous_tilts: &'a wgpu::Buffer,
    /// This step's `array<GpuTilt>`.
    pub tilts: &'a wgpu::Buffer,
}

impl KernelArgs for SolveFusedArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.contact_work,
            self.manifolds,
            self.contacts,
            self.bodies,
            self.previous_colors,
            self.color_state,
            self.color_marks,
            self.color_scratch,
            self.color_offsets,
            self.color_order,
            self.poses,
            self.velocities,
            self.solver_bodies,
            self.constraints,
            self.previous_tilts,
            self.tilts,
        ]
    }
}
