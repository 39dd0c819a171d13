// requires: common/solver_types.wgsl solver/common/solver_constants.wgsl sleep/common/sleep_types.wgsl
// Constants of the sleep kernels. Their values are defined once, in tumble-solver (the
// thresholds, shared with the CPU step) and crates/tumble-gpu/src/sleep/constants.rs (the
// encodings), and supplied at pipeline creation; none has a default here.

// An island sleeps when every body in it has rested this long (s).
override TIME_TO_SLEEP: f32;
// A body rests while its speed is below this (m/s) ...
override LINEAR_SLEEP_TOLERANCE: f32;
// ... and its angular speed below this (rad/s).
override ANGULAR_SLEEP_TOLERANCE: f32;
// The island label of an awake body (sleeping bodies hold their island's label).
override AWAKE: u32;
// The f32 bits of +infinity: an island's shortest rest time before any body reported one.
override REST_UNSET: u32;

// True when body `kind`, whose island label is `island`, can join an island this step: an
// awake dynamic body (fixed and kinematic bodies are moved by no contact, so they never tie
// two islands together; sleeping bodies are obstacles for the step).
fn is_linkable(kind: u32, island: u32) -> bool {
    return kind == BODY_DYNAMIC && island == AWAKE;
}
