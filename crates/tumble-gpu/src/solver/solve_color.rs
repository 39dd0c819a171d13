//! `solve_color`: one pass (warm start, solve, relax or restitution) over the constraints of
//! one graph color, one thread each, or over the overflow set in one thread. Its CPU twin is
//! tumble-solver's `sweep` of the same pass over the same color order.

use crate::kernel::{KernelArgs, KernelSpec};
use crate::shader::{Binding, ShaderSource, wgsl_file};

use super::constants::{PASS_RELAX, PASS_RESTITUTION, PASS_SOLVE, PASS_WARM_START};
use super::shaders::PASS_COMMON;

/// Kernel: specialized per pass with the `PASS` override.
pub static SOLVE_COLOR: KernelSpec = KernelSpec {
    name: "solve_color",
    source: ShaderSource {
        common: PASS_COMMON,
        kernel: wgsl_file!("solver/solve_color.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// The passes a sweep over the colors can make.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PassKind {
    /// Re-apply last substep's impulses.
    WarmStart,
    /// Biased solve.
    Solve,
    /// Unbiased solve.
    Relax,
    /// Restitution after the substeps.
    Restitution,
}

impl PassKind {
    /// Every pass, in the order of [`Self::index`].
    pub const ALL: [PassKind; 4] = [
        PassKind::WarmStart,
        PassKind::Solve,
        PassKind::Relax,
        PassKind::Restitution,
    ];

    /// The `PASS` override value.
    pub fn code(self) -> u32 {
        match self {
            PassKind::WarmStart => PASS_WARM_START,
            PassKind::Solve => PASS_SOLVE,
            PassKind::Relax => PASS_RELAX,
            PassKind::Restitution => PASS_RESTITUTION,
        }
    }

    /// Position in [`Self::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }
}

/// Buffers of [`SOLVE_COLOR`].
pub struct SolveColorArgs<'a> {
    /// `SolverParams`.
    pub params: &'a wgpu::Buffer,
    /// `ColorPass` naming the color.
    pub pass_color: &'a wgpu::Buffer,
    /// Per-color offsets into `color_order`.
    pub color_offsets: &'a wgpu::Buffer,
    /// Constraint indices grouped by color.
    pub color_order: &'a wgpu::Buffer,
    /// `array<GpuSolverBody>`.
    pub solver_bodies: &'a wgpu::Buffer,
    /// `array<GpuVelocity>`, updated.
    pub velocities: &'a wgpu::Buffer,
    /// `array<GpuConstraint>`, updated.
    pub constraints: &'a wgpu::Buffer,
}

impl KernelArgs for SolveColorArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.pass_color,
            self.color_offsets,
            self.color_order,
            self.solver_bodies,
            self.velocities,
            self.constraints,
        ]
    }
}
