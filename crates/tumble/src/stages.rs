//! The step's stages as CPU functions, named as in docs/architecture.md: `update_aabbs`,
//! `broad_phase`, `narrow_phase`, `color`, `solve`, `finish` (and the sleep stage,
//! [`tumble_solver::SleepState`]).
//!
//! Each stage lives in the layer crate of its stage ([`tumble_broad::update_aabbs`],
//! [`tumble_narrow::pair_margin`], [`tumble_solver::stages`]); this module names them for
//! the facade's users. Each takes plain slices and returns plain data, so a backend can
//! replace any one of them (the hybrid backend runs the first three on the GPU and hands
//! their output to the CPU `color`, `solve` and `finish`). The order they run in is
//! [`tumble_solver::Stage::ALL`].

use tumble_geometry::Real;
use tumble_solver::{Body, BodyState};

pub use tumble_solver::Stage;
pub use tumble_solver::stages::{
    NarrowPhaseOutput, broad_phase, color, finish, narrow_phase, top_down_order, update_aabbs,
};
/// Stage `solve`: the configured solver for one step ([`tumble_solver::solve`], and with only
/// some effects [`tumble_solver::solve_with_effects`]).
pub use tumble_solver::{solve, solve_with_effects};

/// The speculative margin of a pair: the base margin plus how far the two boxes can close in
/// one step (relative speed of the centres plus the rim speed of each spin, times `dt`); see
/// [`tumble_narrow::pair_margin`].
pub fn pair_margin(a: (&Body, &BodyState), b: (&Body, &BodyState), margin: Real, dt: Real) -> Real {
    use tumble_solver::stages::box_motion;
    tumble_narrow::pair_margin(&box_motion(a.0, a.1), &box_motion(b.0, b.1), margin, dt)
}
