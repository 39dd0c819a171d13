//! Shared helpers for the criterion benches.
#![warn(missing_docs)]
pub mod effect_pool;
pub mod gpu_pool;
