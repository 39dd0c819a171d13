//! Stage 6: contacts to new velocities and in-step displacements.

use tumble_geometry::{Real, Vec3};
use tumble_solver::{Body, BodyState, Coloring, Contact, Effects, SolveStats, SolverConfig};

/// Runs the configured solver (see [`tumble_solver::solve`]) for one step.
pub fn solve(
    bodies: &[Body],
    states: &mut [BodyState],
    contacts: &mut [Contact],
    coloring: &Coloring,
    config: &SolverConfig,
    dt: Real,
    gravity: &Vec3,
) -> SolveStats {
    tumble_solver::solve(bodies, states, contacts, coloring, config, dt, gravity)
}

/// [`solve`] running only `effects` (see [`tumble_solver::solve_with_effects`]).
#[allow(clippy::too_many_arguments)]
pub fn solve_with_effects(
    bodies: &[Body],
    states: &mut [BodyState],
    contacts: &mut [Contact],
    coloring: &Coloring,
    config: &SolverConfig,
    dt: Real,
    gravity: &Vec3,
    effects: &Effects,
) -> SolveStats {
    tumble_solver::solve_with_effects(
        bodies, states, contacts, coloring, config, dt, gravity, effects,
    )
}
