//! The step's stages as CPU functions, named as in docs/architecture.md: `update_aabbs`,
//! `broad_phase`, `narrow_phase`, `color`, `solve`, `finish`.
//!
//! Each stage takes plain slices and returns plain data, so a backend can replace any one of
//! them (the hybrid backend runs the first three on the GPU and hands their output to the CPU
//! `color` and `solve`). [`crate::World::step`] calls them in order and times each.

mod broad_phase;
mod color;
mod finish;
mod narrow_phase;
mod solve;
mod update_aabbs;

pub use broad_phase::broad_phase;
pub use color::color;
pub use finish::finish;
pub use narrow_phase::{NarrowPhaseOutput, narrow_phase, pair_margin};
pub use solve::{solve, solve_with_effects};
pub use update_aabbs::update_aabbs;
