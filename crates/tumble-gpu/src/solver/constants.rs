//! Constants of the solver stages, defined once here and handed to the solver pipelines as
//! WGSL `override` values (declared without defaults in `shaders/solver/common/solver_constants.wgsl`).

use super::layout::{GpuConstraint, GpuConstraintPoint};

/// Graph colors (tumble-solver's `GRAPH_COLOR_COUNT`, Box2D v3's 24).
pub const GRAPH_COLOR_COUNT: u32 = tumble_solver::GRAPH_COLOR_COUNT as u32;

/// The color of the overflow set (tumble-solver's `OVERFLOW_COLOR`).
pub const OVERFLOW_COLOR: u32 = tumble_solver::OVERFLOW_COLOR;

/// Colors plus the overflow set: the per-color passes dispatched per sweep.
pub const COLOR_SLOTS: u32 = GRAPH_COLOR_COUNT + 1;

/// Threads per workgroup of the per-color passes (`solve_color`). Each thread visits one
/// constraint, a chain of dependent loads, so a pass is latency-bound: a color of a few
/// thousand constraints in 256-thread workgroups sits on a handful of SMs, and one-warp
/// workgroups spread the same threads over many more. The results do not depend on it.
/// Measured on an H200 (Vulkan; `benches/src/bin/dispatch_probe.rs`, wide path, 4 substeps,
/// solve pass per step, with the passes writing back only impulses): pyramid of 24 (35,720
/// manifolds) 2.97 / 2.16 / 1.82 ms at 128 / 64 / 32 threads against 6.17 ms at 256 with
/// whole-constraint writes; pyramid of 50 (328,235) 5.58 / 4.95 / 4.78 against 7.78 ms.
pub const COLOR_PASS_WORKGROUP_SIZE: u32 = 32;

/// Entry of the coloring tally that counts the constraints undecided after the first round
/// (appended to the list `color_finish` continues from).
pub const TALLY_UNDECIDED: u32 = 0;
/// First entry of the coloring tally's per-color counts (one per color slot, overflow last).
pub const TALLY_COUNTS: u32 = 1;
/// Entries of the coloring tally, zeroed before every step's coloring.
pub const COLOR_TALLY_LEN: u32 = TALLY_COUNTS + COLOR_SLOTS;
/// Bytes of one row of the constraint store: constraints are kept as a structure of arrays of
/// 16-byte rows (`shaders/solver/common/constraint_store.wgsl`), row `r` of the constraint in
/// slot `s` at row index `r * stride + s`.
pub const CONSTRAINT_ROW_BYTES: usize = 16;
/// Rows of one `GpuConstraint`.
pub const CONSTRAINT_ROWS: u32 = (size_of::<GpuConstraint>() / CONSTRAINT_ROW_BYTES) as u32;
/// Rows of one `GpuConstraintPoint`.
pub const CONSTRAINT_POINT_ROWS: u32 =
    (size_of::<GpuConstraintPoint>() / CONSTRAINT_ROW_BYTES) as u32;
/// Rows before the first point.
pub const CONSTRAINT_HEADER_ROWS: u32 =
    CONSTRAINT_ROWS - CONSTRAINT_POINT_ROWS * tumble_geometry::MAX_MANIFOLD_POINTS as u32;
const _: () = assert!(size_of::<GpuConstraint>().is_multiple_of(CONSTRAINT_ROW_BYTES));
const _: () = assert!(size_of::<GpuConstraintPoint>().is_multiple_of(CONSTRAINT_ROW_BYTES));
/// Entries of the color offsets buffer: `offsets[c]..offsets[c + 1]` for every slot.
pub const COLOR_OFFSETS_LEN: u32 = COLOR_SLOTS + 1;

/// Color and proposal of a constraint not decided yet (tumble-solver's `NO_COLOR`).
pub const NO_COLOR: u32 = tumble_solver::NO_COLOR;

/// The color of a manifold without points (tumble-solver's `EMPTY_COLOR`, one past the
/// overflow set): no constraint, in no color's range.
pub const EMPTY_COLOR: u32 = tumble_solver::EMPTY_COLOR;

/// Coloring rounds per step, on every path (tumble-solver's `COLOR_ROUNDS`, the rounds of
/// `tumble_solver::color_in_rounds`).
pub const COLOR_ROUNDS: u32 = tumble_solver::COLOR_ROUNDS;

const _: () = assert!(EMPTY_COLOR == COLOR_SLOTS);

/// `GpuBody::kind` of a fixed body.
pub const BODY_FIXED: u32 = 0;
/// `GpuBody::kind` of a dynamic body.
pub const BODY_DYNAMIC: u32 = 1;
/// `GpuBody::kind` of a kinematic body.
pub const BODY_KINEMATIC: u32 = 2;

/// `GpuBody::locks`: bit `k` locks translation along world axis `k`, bit
/// `k + LOCK_ROTATION_SHIFT` rotation about it.
pub const LOCK_ROTATION_SHIFT: u32 = 3;

/// `GpuConstraint::flags`: body A is dynamic (the solver writes its velocity).
pub const CONSTRAINT_DYNAMIC_A: u32 = 1;
/// `GpuConstraint::flags`: body B is dynamic.
pub const CONSTRAINT_DYNAMIC_B: u32 = 2;

/// Smallest cosine between a pair's normal last step and now (in body A's frame) for its tilt
/// impulse to carry over: tumble-solver's contact-cache tolerance (the cosine of 5 degrees).
pub const PERSIST_NORMAL_COS: f32 = tumble_solver::PERSIST_NORMAL_COS;

/// What a per-color pass does: re-apply the accumulated impulses.
pub const PASS_WARM_START: u32 = 0;
/// Biased solve (position feedback on).
pub const PASS_SOLVE: u32 = 1;
/// Relax (position feedback off).
pub const PASS_RELAX: u32 = 2;
/// Restitution after the substeps.
pub const PASS_RESTITUTION: u32 = 3;

/// Every solver override value, by WGSL name (the shared ones of
/// [`crate::constants::shader_constants`] come on top).
pub fn solver_constants() -> Vec<(&'static str, f64)> {
    use super::fused::FUSED_SHARED_BODIES;
    use super::solve_step::{SOLVE_STEP_WAIT_LIMIT, SOLVE_STEP_WORKGROUP_SIZE};
    use tumble_solver::{MAX_LINEAR_SPEED, MAX_ROTATION_PER_SUBSTEP};
    crate::constants::override_values![
        GRAPH_COLOR_COUNT,
        FUSED_SHARED_BODIES,
        COLOR_PASS_WORKGROUP_SIZE,
        SOLVE_STEP_WORKGROUP_SIZE,
        SOLVE_STEP_WAIT_LIMIT,
        OVERFLOW_COLOR,
        TALLY_UNDECIDED,
        TALLY_COUNTS,
        CONSTRAINT_ROWS,
        CONSTRAINT_HEADER_ROWS,
        CONSTRAINT_POINT_ROWS,
        NO_COLOR,
        COLOR_ROUNDS,
        EMPTY_COLOR,
        BODY_FIXED,
        BODY_DYNAMIC,
        BODY_KINEMATIC,
        LOCK_ROTATION_SHIFT,
        CONSTRAINT_DYNAMIC_A,
        CONSTRAINT_DYNAMIC_B,
        MAX_ROTATION_PER_SUBSTEP,
        MAX_LINEAR_SPEED,
        PERSIST_NORMAL_COS,
        PASS_WARM_START,
        PASS_SOLVE,
        PASS_RELAX,
        PASS_RESTITUTION,
        GYROSCOPIC_NEWTON_ITERATIONS = tumble_solver::GYROSCOPIC_NEWTON_ITERATIONS as u32,
    ]
}
