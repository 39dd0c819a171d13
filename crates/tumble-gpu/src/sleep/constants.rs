//! Constants of the sleep kernels, defined once here (the thresholds come from tumble-solver,
//! which the CPU step reads too) and handed to the shaders as `override` values.

use tumble_solver::{ANGULAR_SLEEP_TOLERANCE, LINEAR_SLEEP_TOLERANCE, TIME_TO_SLEEP};

/// The island label of an awake body (tumble-solver's); a sleeping body holds its island's
/// label, the smallest body index of the island when it fell asleep.
pub use tumble_solver::AWAKE;

/// The bits of `f32::INFINITY`: an island's shortest rest time before any of its bodies
/// reported one (the minimum over the bits of non-negative floats is the minimum float).
pub const REST_UNSET: u32 = 0x7f80_0000;

/// Rounds of hooking and pointer jumping in the island search. A round at least halves the
/// longest chain of labels still to follow, so chains of `2^ISLAND_ROUNDS` bodies finish:
/// in the CPU twin's runs, a shuffled chain of 16,000 bodies (the worst shape tried: long and
/// in scattered index order) took 14 rounds and random graphs of 1,200 bodies at most 10. A
/// step whose search did not finish lets nothing fall asleep, so a larger scene only sleeps
/// later, never wrongly.
pub const ISLAND_ROUNDS: u32 = 16;

/// The override values of the sleep kernels, by WGSL name.
pub fn sleep_constants() -> Vec<(&'static str, f64)> {
    crate::constants::override_values![
        TIME_TO_SLEEP,
        LINEAR_SLEEP_TOLERANCE,
        ANGULAR_SLEEP_TOLERANCE,
        AWAKE,
        REST_UNSET,
    ]
}

// Checked when the crate compiles: the infinity the shaders start from, and a label that no
// body index can take.
const _: () = assert!(REST_UNSET == f32::INFINITY.to_bits());
const _: () = assert!(crate::MAX_BODIES < AWAKE);
