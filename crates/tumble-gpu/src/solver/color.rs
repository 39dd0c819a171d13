//! The `color` stage on the GPU: `color_propose` and `color_resolve` run the first (seeded)
//! round with one thread per constraint, `color_finish` runs the remaining rounds in one
//! workgroup, counts the colors and writes the per-color dispatch sizes; a stable radix sort
//! by color then gives the constraint order. The CPU twin is `tumble_solver::color_in_rounds`
//! (re-exported here), the same rounds on the host.

use crate::kernel::kernel;

kernel! {
    /// Buffers of [`COLOR_PROPOSE`] and [`COLOR_RESOLVE`].
    pub struct ColorRoundArgs {
        /// `SolverParams` (for the body count).
        params,
        /// The contacts' `WorkList`.
        contact_work,
        /// `array<GpuManifold>`.
        manifolds,
        /// `array<GpuBody>`.
        bodies,
        /// Last step's `array<ColorSlot>`.
        previous_colors,
        /// This step's `array<ColorSlot>`.
        color_state,
        /// Used-color masks then claims, `u32`.
        color_marks,
    }
    /// Kernel: round 0 proposals, one thread per constraint.
    pub static COLOR_PROPOSE = "solver/color_propose.wgsl";
    /// Kernel: round 0 decisions, one thread per constraint.
    pub static COLOR_RESOLVE = "solver/color_resolve.wgsl";
}

kernel! {
    /// Buffers of [`COLOR_FINISH`]: those of [`ColorRoundArgs`], then its own.
    pub struct ColorFinishArgs {
        /// `SolverParams` (for the body count).
        params,
        /// The contacts' `WorkList`.
        contact_work,
        /// `array<GpuManifold>`.
        manifolds,
        /// `array<GpuBody>`.
        bodies,
        /// Last step's `array<ColorSlot>`.
        previous_colors,
        /// This step's `array<ColorSlot>`.
        color_state,
        /// Used-color masks then claims, `u32`.
        color_marks,
        /// Two lists of undecided constraints, `2 * capacity` `u32`.
        color_scratch,
        /// Output: `COLOR_OFFSETS_LEN` offsets.
        color_offsets,
        /// Output: `array<DispatchArgs>`, one per color slot.
        color_args,
        /// Output: sort keys (the colors).
        sort_keys,
        /// Output: sort values (the constraint indices).
        sort_values,
    }
    /// Kernel: the remaining rounds, counts, offsets, dispatch sizes and sort keys (one
    /// workgroup).
    pub static COLOR_FINISH = "solver/color_finish.wgsl";
}

pub use tumble_solver::{ColorCandidate, color_in_rounds, color_priority, hash_u32};
