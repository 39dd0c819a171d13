//! The tilt rows belong to a face patch of three or more points. A pair whose patch shrinks to
//! an edge or a point (two points or one) keeps the normal within the persistence cone, so the
//! cache hands it last step's tilt impulse; with no tilt row to clamp it, that impulse must not
//! act, or it spins the box every substep and is stored back unchanged for the next step.

use tumble_geometry::{Point3, Pose, Real, Vec3};

use super::{floor, gravity, manifold, material, solve_copy, unit_cube};
use crate::{Body, BodyState, Contact, SolverConfig, SolverKind, color_constraints};

/// A unit cube (1 kg) resting on the fixed floor along its bottom edge z = 0 (two points at
/// x = -0.5 and x = 0.5), carrying `tilt` from an earlier step; the cube's state after one
/// solved step and the tilt impulse it leaves for the next.
fn edge_step(kind: SolverKind, tilt: Vec3) -> (BodyState, Vec3) {
    let m = material(0.5, 0.0);
    let bodies: [Body; 2] = [
        floor(m),
        unit_cube(1.0, Pose::translation(0.0, 0.5, 0.0), m),
    ];
    let points: Vec<(Point3, Real, u32)> = [-0.5, 0.5]
        .iter()
        .enumerate()
        .map(|(id, &x)| (Point3::new(x, 0.0, 0.0), 0.0, id as u32))
        .collect();
    let mut contact = Contact::new(0, 1, manifold(Vec3::y(), &points));
    contact.tilt_impulse = tilt;
    let config = SolverConfig {
        kind,
        ..SolverConfig::default()
    };
    let coloring = color_constraints(&[(0, 1)], &[false, true]);
    let states = [BodyState::default(); 2];
    let (states, contacts, _) =
        solve_copy(&bodies, &states, &[contact], &coloring, &config, &gravity());
    (states[1], contacts[0].tilt_impulse)
}

#[test]
fn a_carried_tilt_impulse_does_not_act_on_an_edge_contact() {
    for kind in [SolverKind::SoftStep, SolverKind::Baumgarte] {
        let (fresh, fresh_tilt) = edge_step(kind, Vec3::zeros());
        // 0.5 N m s about x on a cube of inertia 1/6 kg m^2 would be 3 rad/s if it acted.
        let (carried, carried_tilt) = edge_step(kind, Vec3::new(0.5, 0.0, 0.2));
        // Bit for bit: the carried impulse is dropped, so the step is the fresh one.
        assert_eq!(carried.angular_velocity, fresh.angular_velocity, "{kind:?}");
        assert_eq!(carried.linear_velocity, fresh.linear_velocity, "{kind:?}");
        // And nothing is stored back to be carried again.
        assert_eq!(carried_tilt, Vec3::zeros(), "{kind:?}");
        assert_eq!(fresh_tilt, Vec3::zeros(), "{kind:?}");
    }
}
