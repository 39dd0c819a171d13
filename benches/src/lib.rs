//! Shared helpers for the criterion benches.
#![warn(missing_docs)]
pub mod effect_pool;
pub mod gpu_pool;

/// The value after `--name` on the command line, parsed, or `default` when it is missing or
/// does not parse (the table binaries' options).
pub fn arg(name: &str, default: usize) -> usize {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// The solver's bodies and states of a scene (shared with the tests).
pub use tumble_tests::scene_support::bodies_of;
