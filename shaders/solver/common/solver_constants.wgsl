// requires: common/solver_types.wgsl
// Constants of the solver stages. Their values are defined once, in
// crates/tumble-gpu/src/solver/constants.rs, and supplied at pipeline creation; the structural
// ones have no default here, so a pipeline built without them fails instead of drifting.

// Graph colors; a constraint that fits in none gets OVERFLOW_COLOR (= GRAPH_COLOR_COUNT).
override GRAPH_COLOR_COUNT: u32;
override OVERFLOW_COLOR: u32;
// Color (and proposal) of a constraint not decided yet.
override NO_COLOR: u32;
// Color of a manifold without points (a candidate pair not in contact): in no color's range.
override EMPTY_COLOR: u32;
// Rounds of the coloring on every path; constraints undecided after them overflow.
override COLOR_ROUNDS: u32;
// GpuBody.kind values.
override BODY_FIXED: u32;
override BODY_DYNAMIC: u32;
override BODY_KINEMATIC: u32;
// GpuBody.locks: bit k locks translation along world axis k, bit k + LOCK_ROTATION_SHIFT
// locks rotation about it.
override LOCK_ROTATION_SHIFT: u32;
// GpuConstraint.flags bits: the solver writes body A (B) because it is dynamic.
override CONSTRAINT_DYNAMIC_A: u32;
override CONSTRAINT_DYNAMIC_B: u32;
// Guards of integrate_positions (tumble_solver's MAX_ROTATION_PER_SUBSTEP, MAX_LINEAR_SPEED).
override MAX_ROTATION_PER_SUBSTEP: f32;
override MAX_LINEAR_SPEED: f32;
// Smallest cosine between last step's normal and this step's (in body A's frame) for a
// pair's tilt impulse to carry over (tumble-solver's PERSIST_NORMAL_COS).
override PERSIST_NORMAL_COS: f32;
// Threads per workgroup of the per-color passes (solve_color), whose dispatch sizes
// color_plan writes.
override COLOR_PASS_WORKGROUP_SIZE: u32;
// Threads per workgroup of solve_step.
override SOLVE_STEP_WORKGROUP_SIZE: u32;
// The coloring tally (color_withdraw, color_finish, color_count, color_plan): entry
// TALLY_UNDECIDED counts the constraints left after the first round, entries from
// TALLY_COUNTS on the constraints of each color, overflow last.
override TALLY_UNDECIDED: u32;
override TALLY_COUNTS: u32;
// Rows of 16 bytes of a GpuConstraint in the constraint store (constraint_store.wgsl): all
// of them, those before the first point, and those of one point.
override CONSTRAINT_ROWS: u32;
override CONSTRAINT_HEADER_ROWS: u32;
override CONSTRAINT_POINT_ROWS: u32;
// What a per-color pass does to each constraint.
override PASS_WARM_START: u32;
override PASS_SOLVE: u32;
override PASS_RELAX: u32;
override PASS_RESTITUTION: u32;

// Effects compiled in or out per scene (Effects in solver/constants.rs). Turning one off
// never changes a result: it only removes work whose result is known to be zero.
override ENABLE_FRICTION: bool = true;
override ENABLE_RESTITUTION: bool = true;
override ENABLE_GRAVITY: bool = true;
override ENABLE_ROTATION: bool = true;
