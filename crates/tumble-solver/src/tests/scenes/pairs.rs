//! Two bodies meeting in free space: head-on collisions, a kinematic pusher, and the contact
//! stiffness between two dynamic boxes.

use tumble_geometry::Point3;

use super::*;
use crate::BodyKind;
use crate::tests::{assert_close, manifold};

fn head_on(ma: Real, mb: Real, v: Real, restitution: Real, config: &SolverConfig) -> (Real, Real) {
    let m = material(0.5, restitution);
    let mut bodies = [
        unit_cube(ma, Pose::translation(0.0, 0.0, 0.0), m),
        unit_cube(mb, Pose::translation(1.0, 0.0, 0.0), m),
    ];
    let mut states = [
        BodyState::moving(Vec3::new(v, 0.0, 0.0), Vec3::zeros()),
        BodyState::default(),
    ];
    let mut contacts = [Contact::new(
        0,
        1,
        manifold(Vec3::x(), &[(Point3::new(0.5, 0.0, 0.0), 0.0, 0)]),
    )];
    step_free(&mut bodies, &mut states, &mut contacts, config);
    for s in &states {
        assert!(
            s.angular_velocity.norm() < 1e-6,
            "a central impact spins nothing"
        );
    }
    (states[0].linear_velocity.x, states[1].linear_velocity.x)
}

#[test]
fn equal_boxes_colliding_head_on_conserve_momentum_and_exchange_it_when_elastic() {
    for config in [SolverConfig::default(), SolverConfig::baumgarte()] {
        // Perfectly inelastic: both leave at v / 2.
        let (va, vb) = head_on(1.0, 1.0, 2.0, 0.0, &config);
        assert_close("inelastic a", va.into(), 1.0, 1e-4);
        assert_close("inelastic b", vb.into(), 1.0, 1e-4);
        // Elastic: the velocities are exchanged.
        let (va, vb) = head_on(1.0, 1.0, 2.0, 1.0, &config);
        assert_close("elastic a", va.into(), 0.0, 1e-4);
        assert_close("elastic b", vb.into(), 2.0, 1e-4);
        // Elastic, 1 kg on 3 kg: v_a = (m_a - m_b) / (m_a + m_b) v = -1, v_b = 2 m_a / (m_a + m_b) v = 1.
        let (va, vb) = head_on(1.0, 3.0, 2.0, 1.0, &config);
        assert_close("1:3 a", va.into(), -1.0, 1e-4);
        assert_close("1:3 b", vb.into(), 1.0, 1e-4);
        assert_close("momentum", (va + 3.0 * vb).into(), 2.0, 1e-5);
    }
}

#[test]
fn a_kinematic_body_pushes_a_box_and_keeps_its_own_velocity() {
    let config = SolverConfig::baumgarte();
    for kinematic_first in [true, false] {
        let m = material(0.5, 0.0);
        let pusher = crate::tests::body(
            BodyKind::Kinematic,
            Vec3::repeat(0.5),
            Pose::translation(0.0, 0.0, 0.0),
            1.0,
            m,
        );
        let cube = unit_cube(1.0, Pose::translation(1.0, 0.0, 0.0), m);
        let (mut bodies, normal, k, d) = if kinematic_first {
            ([pusher, cube], Vec3::x(), 0, 1)
        } else {
            ([cube, pusher], -Vec3::x(), 1, 0)
        };
        let mut states = [BodyState::default(); 2];
        states[k].linear_velocity = Vec3::new(1.0, 0.0, 0.0);
        let point = Point3::new(0.5, 0.0, 0.0);
        let mut contacts = [Contact::new(0, 1, manifold(normal, &[(point, 0.0, 0)]))];
        step_free(&mut bodies, &mut states, &mut contacts, &config);
        // Infinite mass: the pusher's velocity is its own, the box takes it on.
        assert_eq!(states[k].linear_velocity, Vec3::new(1.0, 0.0, 0.0));
        assert_close("pushed box", states[d].linear_velocity.x.into(), 1.0, 1e-5);
        assert_close(
            "kinematic moved",
            bodies[k].pose.translation.x.into(),
            f64::from(DT),
            1e-6,
        );
    }
}

/// The overlap `depth` of a box on the floor (one point under its centre), no gravity, no warm
/// start: the velocity and displacement one step of `config` gives it.

#[test]
fn a_contact_between_two_dynamic_boxes_uses_the_contact_hertz() {
    // Box B overlaps box A by 1 cm, both 1 kg, no floor, no gravity: the effective mass is
    // 1/2 kg and the dynamic pair keeps the 5 Hz asked for (not the floor's doubled 10 Hz).
    let h = f64::from(DT);
    let d: Real = 0.01;
    let m = material(0.5, 0.0);
    let mut bodies = [
        unit_cube(1.0, Pose::translation(0.0, 0.0, 0.0), m),
        unit_cube(1.0, Pose::translation(0.0, 1.0 - d, 0.0), m),
    ];
    let mut states = [BodyState::default(); 2];
    let point = Point3::new(0.0, 0.5 - 0.5 * d, 0.0);
    let mut contacts = [Contact::new(0, 1, manifold(Vec3::y(), &[(point, d, 0)]))];
    step_free(
        &mut bodies,
        &mut states,
        &mut contacts,
        &one_substep(5.0, 0),
    );
    let (bias_rate, mass_scale, _) = soft(5.0, 1.0, h);
    let relative = mass_scale * bias_rate * f64::from(d);
    assert_close(
        "b",
        states[1].linear_velocity.y.into(),
        relative / 2.0,
        1e-5,
    );
    assert_close(
        "a",
        states[0].linear_velocity.y.into(),
        -relative / 2.0,
        1e-5,
    );
}
