//! Closed-form cases through the whole solve stage: a box resting on a fixed floor, sliding
//! on it, bouncing, falling onto it from above; two boxes colliding head on; the soft and
//! Baumgarte position feedback; relax passes; warm starting; the visiting order.

mod feedback;
mod floor_box;
mod order;
mod pairs;

use tumble_geometry::{Manifold, Pose, Real, Vec3};

use super::{DT, floor_center, floor_corners, gravity, material, step, unit_cube};
use crate::{
    Body, BodyState, Contact, Effects, SolveStats, SolverConfig, color_constraints, color_contacts,
};

/// One step without gravity, every effect on: bodies meeting in free space.
fn step_free(
    bodies: &mut [Body],
    states: &mut [BodyState],
    contacts: &mut [Contact],
    config: &SolverConfig,
) {
    step(
        bodies,
        states,
        contacts,
        config,
        &Vec3::zeros(),
        &Effects::ALL,
    );
}

/// A unit cube on the fixed floor (bodies 0 and 1), their states and the contact between
/// them; the box starts resting on the floor, at rest, touching it at its four bottom corners.
struct OnFloor {
    bodies: [Body; 2],
    states: [BodyState; 2],
    contact: Contact,
    /// What the contact's manifold is made of, rebuilt from the box's pose.
    geometry: fn(&Body) -> Manifold,
}

impl OnFloor {
    /// The box of `mass` with `friction` and `restitution` (the floor has the same), resting.
    fn new(mass: Real, friction: Real, restitution: Real) -> Self {
        let m = material(friction, restitution);
        let bodies = [
            super::floor(m),
            unit_cube(mass, Pose::translation(0.0, 0.5, 0.0), m),
        ];
        let contact = Contact::new(0, 1, floor_corners(&bodies[1]));
        Self {
            bodies,
            states: [BodyState::default(); 2],
            contact,
            geometry: floor_corners,
        }
    }

    /// The box's centre moved to `y` (0.5 rests on the floor), its contact rebuilt there.
    fn at_height(mut self, y: Real) -> Self {
        self.bodies[1].pose = Pose::translation(0.0, y, 0.0);
        self.contact = Contact::new(0, 1, (self.geometry)(&self.bodies[1]));
        self
    }

    /// The contact made of one point under the box's centre instead of its corners.
    fn center_point(mut self) -> Self {
        self.geometry = floor_center;
        self.contact = Contact::new(0, 1, floor_center(&self.bodies[1]));
        self
    }

    /// The box moving at `velocity`, not spinning.
    fn moving(mut self, velocity: Vec3) -> Self {
        self.states[1] = BodyState::moving(velocity, Vec3::zeros());
        self
    }

    /// One step of the contact as it stands (carried impulses included) under `gravity`.
    fn step(&mut self, config: &SolverConfig, gravity: &Vec3, effects: &Effects) {
        let mut contacts = [self.contact];
        step(
            &mut self.bodies,
            &mut self.states,
            &mut contacts,
            config,
            gravity,
            effects,
        );
        self.contact = contacts[0];
    }

    /// `steps` steps under gravity, the manifold rebuilt each step from the box's pose (same
    /// ids, so the impulses carry over as a cache hit would carry them).
    fn run(&mut self, config: &SolverConfig, effects: &Effects, steps: usize) {
        for _ in 0..steps {
            self.contact.manifold = (self.geometry)(&self.bodies[1]);
            self.step(config, &gravity(), effects);
        }
    }

    /// The box's overlap with the floor, m.
    fn depth(&self) -> f64 {
        0.5 - f64::from(self.bodies[1].pose.translation.y)
    }
}

/// The soft-step coefficients of the documented formulas, in f64: `(bias_rate, mass_scale,
/// impulse_scale)` for `hertz`, damping ratio `zeta` and substep `h`.
fn soft(hertz: f64, zeta: f64, h: f64) -> (f64, f64, f64) {
    let omega = 2.0 * std::f64::consts::PI * hertz;
    let a1 = 2.0 * zeta + h * omega;
    let a2 = h * omega * a1;
    (omega / a1, a2 / (1.0 + a2), 1.0 / (1.0 + a2))
}

/// One substep of one pass (plus `relax` relax passes) at `hertz`, critically damped, cold.
fn one_substep(hertz: Real, relax: u32) -> SolverConfig {
    SolverConfig {
        substeps: 1,
        iterations: 1,
        relax_iterations: relax,
        warm_start: false,
        contact_hertz: hertz,
        damping_ratio: 1.0,
        ..SolverConfig::default()
    }
}
