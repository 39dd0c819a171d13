//! `solve_fused`: the color and solve stages in one workgroup and one dispatch, for scenes
//! small enough that per-dispatch overhead dominates. It computes exactly what the wide path
//! computes (same functions, same order), so the choice between them never changes a result.
//! `solve_fused_shared` is the same stage with the bodies in workgroup memory, over the same
//! buffers (`shaders/solver/common/fused_solve.wgsl` is their common body).

use crate::kernel::{KernelSpec, kernel, renamed};

kernel! {
    /// Buffers of [`SOLVE_FUSED`].
    pub struct SolveFusedArgs {
        /// `SolverParams`.
        params,
        /// The contacts' `WorkList`.
        contact_work,
        /// `array<GpuManifold>`.
        manifolds,
        /// `array<GpuContact>` (points), impulses updated.
        contacts,
        /// `array<GpuBody>`.
        bodies,
        /// Last step's `array<ColorSlot>`.
        previous_colors,
        /// This step's `array<ColorSlot>`.
        color_state,
        /// Used-color masks and claims.
        color_marks,
        /// Undecided lists.
        color_scratch,
        /// Per-color offsets.
        color_offsets,
        /// Constraint order by color.
        color_order,
        /// `array<GpuPose>`, updated.
        poses,
        /// `array<GpuVelocity>`, updated.
        velocities,
        /// `array<GpuSolverBody>`.
        solver_bodies,
        /// The constraint store (`GpuConstraint` rows, by slot).
        constraints,
        /// Last step's `array<GpuTilt>`.
        previous_tilts,
        /// This step's `array<GpuTilt>`.
        tilts,
    }
    /// Kernel: a single workgroup.
    pub static SOLVE_FUSED = "solver/solve_fused.wgsl";
}

/// Kernel: [`SOLVE_FUSED`] with the bodies in workgroup memory, taking [`SolveFusedArgs`]; the
/// shader names the two body buffers `velocity_buffer` and `solver_body_buffer` (its workgroup
/// copies take the fields' names).
pub static SOLVE_FUSED_SHARED: KernelSpec = KernelSpec::new(
    crate::shader::file("solver/solve_fused_shared.wgsl"),
    &SHARED_BINDINGS,
);

const SHARED_BINDINGS: [&str; SolveFusedArgs::<'static>::NAMES.len()] = renamed(
    SolveFusedArgs::NAMES,
    &[
        ("velocities", "velocity_buffer"),
        ("solver_bodies", "solver_body_buffer"),
    ],
);

/// Bodies [`SOLVE_FUSED_SHARED`] holds in workgroup memory: 128 bytes each (a velocity and a
/// solver state), 14 KiB in all, within the 16 KiB of workgroup memory every WebGPU device
/// offers, with room for the coloring's own workgroup variables.
pub const FUSED_SHARED_BODIES: u32 = 112;
