//! Shared helpers for the criterion benches.
#![warn(missing_docs)]
pub mod cli;
pub mod effect_pool;
pub mod gpu_pool;
pub mod random_pile;

/// The solver's bodies and states of a scene (shared with the tests).
pub use tumble_tests::scene_support::bodies_of;
