//! Stage 6: contacts to new velocities and in-step displacements.

use tumble_geometry::{Real, Vec3};
use tumble_solver::{Body, BodyState, Coloring, Contact, SolveStats, SolverConfig};

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
