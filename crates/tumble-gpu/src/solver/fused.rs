//! `solve_fused`: the color and solve stages in one workgroup and one dispatch, for scenes
//! small enough that per-dispatch overhead dominates. It computes exactly what the wide path
//! computes (same functions, same order), so the choice between them never changes a result.

use crate::kernel::kernel;

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
