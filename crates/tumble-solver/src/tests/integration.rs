//! Integration: semi-implicit Euler substep by substep, the damping law, locks, body kinds,
//! the speed clamps, the Cayley rotation update, and the gyroscopic term's invariants.

use tumble_geometry::{Pose, Real, Rot, Vec3};

use super::reference::{M, V, m64, v64};
use super::{G, assert_close, assert_close3, body, gravity, material, unit_cube};
use crate::{
    Body, BodyKind, BodyState, Locks, MAX_LINEAR_SPEED, MAX_ROTATION_PER_SUBSTEP, begin_step,
    finalize_bodies, gyroscopic_midpoint, integrate_positions, integrate_velocities,
    integrate_velocities_with,
};

fn cube_at(y: Real) -> Body {
    unit_cube(1.0, Pose::translation(0.0, y, 0.0), material(0.5, 0.0))
}

/// The 1 x 2 x 3 box of density 1 (moments 13/2, 10/2, 5/2 kg m^2), turned.
fn brick(rotation: Rot) -> Body {
    body(
        BodyKind::Dynamic,
        Vec3::new(0.5, 1.0, 1.5),
        Pose::from_parts(Vec3::zeros().into(), rotation),
        1.0,
        material(0.5, 0.0),
    )
}

#[test]
fn every_substep_of_free_fall_is_semi_implicit_euler() {
    let bodies = [cube_at(10.0)];
    let v0 = Vec3::new(1.0, 2.0, -0.5);
    let mut states = [BodyState::moving(v0, Vec3::zeros())];
    let h: Real = 1.0 / 240.0;
    let (mut v, mut x) = (v64(&v0), V::zeros());
    for k in 1..=50 {
        integrate_velocities(&bodies, &mut states, &gravity(), h);
        // Velocity first, then the position with the new velocity.
        v += v64(&gravity()) * f64::from(h);
        assert_close(
            &format!("vy after {k}"),
            states[0].linear_velocity.y.into(),
            v.y,
            1e-5,
        );
        integrate_positions(&bodies, &mut states, h);
        x += v * f64::from(h);
        let what = format!("dp after {k}");
        assert_close3(&what, &states[0].delta_position, &x, 1e-6);
    }
}

#[test]
fn damping_divides_the_velocity_by_one_plus_h_c_each_substep() {
    let mut b = cube_at(0.0);
    b.linear_damping = 2.0;
    b.angular_damping = 5.0;
    let bodies = [b];
    let mut states = [BodyState::moving(
        Vec3::new(3.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 4.0),
    )];
    let h: Real = 0.05;
    let (mut v, mut w) = (V::new(3.0, 0.0, 0.0), 4.0f64);
    for k in 1..=10 {
        integrate_velocities(&bodies, &mut states, &gravity(), h);
        // Gravity first, then the damping factor 1 / (1 + h c).
        v = (v + v64(&gravity()) * 0.05) / (1.0 + 0.05 * 2.0);
        w /= 1.0 + 0.05 * 5.0;
        let what = format!("v after {k}");
        assert_close3(&what, &states[0].linear_velocity, &v, 1e-5);
        assert_close(
            &format!("w after {k}"),
            states[0].angular_velocity.z.into(),
            w,
            1e-6,
        );
    }
}

#[test]
fn locked_axes_neither_move_nor_turn() {
    let mut b = brick(Rot::from_euler_angles(0.3, 0.2, 0.1));
    b.locks = Locks {
        translation: [false, true, false],
        rotation: [true, false, true],
    };
    let bodies = [b];
    let mut states = [BodyState::moving(
        Vec3::new(1.0, 5.0, 0.0),
        Vec3::new(2.0, 3.0, 1.0),
    )];
    let h = 1.0 / 60.0;
    for _ in 0..30 {
        integrate_velocities(&bodies, &mut states, &gravity(), h);
        integrate_positions(&bodies, &mut states, h);
    }
    let s = states[0];
    // Locked y: gravity and the initial 5 m/s do nothing. Locked x and z rotations: only the
    // spin about world y remains, and (the gyroscopic term skipped for locked bodies) it
    // stays 3 rad/s.
    assert_eq!(s.linear_velocity.y, 0.0);
    assert_eq!(s.delta_position.y, 0.0);
    assert_close("free x", s.delta_position.x.into(), 0.5, 1e-5);
    assert_eq!(s.angular_velocity, Vec3::new(0.0, 3.0, 0.0));
    let (axis, angle) = s.delta_rotation.axis_angle().unwrap();
    assert!((axis.into_inner() - Vec3::y()).norm() < 1e-5, "{axis:?}");
    assert!(
        angle > 1.4 && angle < 1.6,
        "half a second at 3 rad/s: {angle}"
    );
}

#[test]
fn fixed_bodies_never_move_and_kinematic_bodies_move_exactly_as_told() {
    let fixed = super::floor(material(0.5, 0.0));
    let kinematic = body(
        BodyKind::Kinematic,
        Vec3::repeat(0.5),
        Pose::identity(),
        1.0,
        material(0.5, 0.0),
    );
    let mut damped = kinematic;
    damped.linear_damping = 4.0;
    let mut bodies = [fixed, damped];
    // A velocity in a fixed body's state is never used. A kinematic body keeps the velocity
    // it is given: no gravity, no damping, and no speed cap (500 m/s > MAX_LINEAR_SPEED).
    let v = Vec3::new(500.0, 0.0, 0.0);
    let w = Vec3::new(0.0, 0.0, 1.0);
    let mut states = [BodyState::moving(v, w), BodyState::moving(v, w)];
    let h = 1.0 / 60.0;
    begin_step(&mut states);
    integrate_velocities(&bodies, &mut states, &gravity(), h);
    integrate_positions(&bodies, &mut states, h);
    assert_eq!(states[0].delta_position, Vec3::zeros());
    assert_eq!(states[1].linear_velocity, v);
    assert_eq!(states[1].angular_velocity, w);
    assert_close(
        "kinematic x",
        states[1].delta_position.x.into(),
        500.0 / 60.0,
        1e-4,
    );
    let before = bodies[0].pose;
    finalize_bodies(&mut bodies, &mut states);
    assert_eq!(bodies[0].pose, before);
    assert_close(
        "kinematic pose",
        bodies[1].pose.translation.x.into(),
        500.0 / 60.0,
        1e-4,
    );
    assert!(
        bodies[1].pose.rotation.angle() > 0.016,
        "the kinematic body turned"
    );
}

#[test]
fn dynamic_speeds_are_clamped_to_the_documented_caps() {
    let bodies = [cube_at(0.0)];
    let h: Real = 1.0 / 60.0;
    let mut states = [BodyState::moving(
        Vec3::new(0.0, 0.0, 1000.0),
        Vec3::new(0.0, 1000.0, 0.0),
    )];
    integrate_positions(&bodies, &mut states, h);
    let s = states[0];
    assert_close(
        "linear cap",
        s.linear_velocity.norm().into(),
        MAX_LINEAR_SPEED.into(),
        1e-3,
    );
    assert_close(
        "moved at the cap",
        s.delta_position.z.into(),
        f64::from(MAX_LINEAR_SPEED * h),
        1e-4,
    );
    // At most an eighth of a turn per substep: |w| = (pi / 4) / h.
    let cap = std::f64::consts::FRAC_PI_4 * 60.0;
    assert_close("angular cap", s.angular_velocity.norm().into(), cap, 1e-3);
    assert!(s.angular_velocity.x == 0.0 && s.angular_velocity.z == 0.0);
    // Below the caps nothing is touched.
    let mut slow = [BodyState::moving(
        Vec3::new(0.0, 0.0, 399.0),
        Vec3::new(0.0, 47.0, 0.0),
    )];
    integrate_positions(&bodies, &mut slow, h);
    assert_eq!(slow[0].linear_velocity, Vec3::new(0.0, 0.0, 399.0));
    assert_eq!(slow[0].angular_velocity, Vec3::new(0.0, 47.0, 0.0));
    assert_close(
        "MAX_ROTATION_PER_SUBSTEP",
        MAX_ROTATION_PER_SUBSTEP.into(),
        std::f64::consts::FRAC_PI_4,
        1e-7,
    );
}

#[test]
fn the_rotation_update_turns_by_two_atan_of_half_h_w_about_w() {
    // The Cayley map: each substep turns by 2 atan(h |w| / 2) about w, composed on the left
    // (w is a world vector). A cube (equal moments, no gyroscopic term) at 6 rad/s about a
    // tilted axis, h = 0.1: 2 atan(0.3) per substep.
    let q0 = Rot::from_euler_angles(0.4, -0.7, 1.1);
    let mut bodies = [unit_cube(
        1.0,
        Pose::from_parts(Vec3::zeros().into(), q0),
        material(0.5, 0.0),
    )];
    let axis = Vec3::new(1.0, 2.0, 2.0) / 3.0;
    let mut states = [BodyState::moving(Vec3::zeros(), axis * 6.0)];
    let h = 0.1;
    begin_step(&mut states);
    for k in 1..=3 {
        integrate_positions(&bodies, &mut states, h);
        let (got_axis, angle) = states[0].delta_rotation.axis_angle().unwrap();
        assert_close(
            &format!("angle after {k}"),
            angle.into(),
            k as f64 * 2.0 * 0.3f64.atan(),
            1e-5,
        );
        assert!((got_axis.into_inner() - axis).norm() < 1e-5, "{got_axis:?}");
        assert!((states[0].delta_rotation.quaternion().norm() - 1.0).abs() < 1e-6);
    }
    let dq = states[0].delta_rotation;
    finalize_bodies(&mut bodies, &mut states);
    assert!(bodies[0].pose.rotation.angle_to(&(dq * q0)) < 1e-5);
    assert_eq!(states[0].delta_rotation, Rot::identity());
    assert_eq!(states[0].delta_position, Vec3::zeros());
}

#[test]
fn begin_step_clears_the_deltas_and_keeps_the_velocities() {
    let mut states = [BodyState {
        linear_velocity: Vec3::new(1.0, 2.0, 3.0),
        angular_velocity: Vec3::new(-1.0, 0.5, 0.0),
        delta_position: Vec3::new(0.1, 0.2, 0.3),
        delta_rotation: Rot::from_euler_angles(0.1, 0.2, 0.3),
    }];
    begin_step(&mut states);
    assert_eq!(
        states[0],
        BodyState::moving(Vec3::new(1.0, 2.0, 3.0), Vec3::new(-1.0, 0.5, 0.0))
    );
}

/// World angular momentum of a free body: `R I R^T w`.
fn momentum(b: &Body, s: &BodyState) -> V {
    let rotation = m64(&(s.delta_rotation * b.pose.rotation)
        .to_rotation_matrix()
        .into_inner());
    let inertia: M = M::from_diagonal(&v64(&b.inertia_local()));
    rotation * inertia * rotation.transpose() * v64(&s.angular_velocity)
}

#[test]
fn a_body_with_two_equal_moments_precesses_with_its_angular_momentum_fixed() {
    // Boxes of 1 x 1 x 2 (moments 5/12, 5/12, 2/12 of the mass) and 2 x 1 x 1 (2/12, 5/12,
    // 5/12): either pair of equal moments. Spinning off their axes, their angular velocity
    // precesses, which only the gyroscopic term produces; L stays put.
    for half in [Vec3::new(0.5, 0.5, 1.0), Vec3::new(1.0, 0.5, 0.5)] {
        let mut bodies = [body(
            BodyKind::Dynamic,
            half,
            Pose::from_parts(Vec3::zeros().into(), Rot::from_euler_angles(0.2, 0.5, -0.3)),
            1.0,
            material(0.5, 0.0),
        )];
        let mut states = [BodyState::moving(Vec3::zeros(), Vec3::new(1.0, 0.5, 3.0))];
        let l0 = momentum(&bodies[0], &states[0]);
        let w0 = states[0].angular_velocity;
        let h = 1.0 / 240.0;
        for _ in 0..240 {
            begin_step(&mut states);
            integrate_velocities(&bodies, &mut states, &Vec3::zeros(), h);
            integrate_positions(&bodies, &mut states, h);
            finalize_bodies(&mut bodies, &mut states);
        }
        let l1 = momentum(&bodies[0], &states[0]);
        // Second-order error at h |w| = 0.013 over a second: ~1e-5 relative; 1e-3 is far
        // from the tens of percent that a missing or wrong gyroscopic term gives.
        assert!(
            (l1 - l0).norm() < 1e-3 * l0.norm(),
            "{half}: L {l0} -> {l1}"
        );
        assert!(
            (states[0].angular_velocity - w0).norm() > 0.1,
            "{half}: w precessed"
        );
        // The rotation stays a unit quaternion.
        assert!((bodies[0].pose.rotation.quaternion().norm() - 1.0).abs() < 1e-6);
    }
}

#[test]
fn a_spin_about_a_principal_axis_is_steady() {
    // Euler's equations: w along a principal axis gives (I w) x w = 0.
    let q = Rot::from_euler_angles(0.3, 0.0, 0.0);
    let bodies = [brick(q)];
    let w = q * Vec3::new(0.0, 0.0, 4.0);
    let mut states = [BodyState::moving(Vec3::zeros(), w)];
    for _ in 0..60 {
        integrate_velocities(&bodies, &mut states, &Vec3::zeros(), 1.0 / 60.0);
        integrate_positions(&bodies, &mut states, 1.0 / 60.0);
    }
    assert!(
        (states[0].angular_velocity - w).norm() < 1e-4,
        "{}",
        states[0].angular_velocity
    );
}

#[test]
fn the_midpoint_rule_is_solved_to_round_off_and_keeps_both_invariants() {
    // I (w1 - w0) = h (I wm) x wm with wm = (w0 + w1) / 2; three Newton steps reach f32
    // round-off up to h |w| of about 1 (a quarter turn per substep would be 1.57).
    let inertia = Vec3::new(6.5, 5.0, 2.5);
    let i64_ = v64(&inertia);
    for (w0, h) in [
        (Vec3::new(0.4, 1.8, 0.5), 0.05),
        (Vec3::new(0.4, 1.8, 0.5), 0.5),
        (Vec3::new(1.0, 1.0, 1.0), 0.5),
        (Vec3::new(0.5, 0.6, 2.0), 0.2),
        (Vec3::new(1.5, 0.3, 1.0), 0.2),
    ] {
        let w1 = gyroscopic_midpoint(&inertia, &w0, h);
        let (a, b) = (v64(&w0), v64(&w1));
        let wm = (a + b) * 0.5;
        let residual =
            i64_.component_mul(&(b - a)) - i64_.component_mul(&wm).cross(&wm) * f64::from(h);
        let l = i64_.component_mul(&a).norm();
        // Converged, the residual is f32 round-off, about 5e-8 of |L|; Newton steps with a
        // wrong Jacobian are still at 3e-6 or more after three iterations here.
        assert!(
            residual.norm() < 1e-6 * l,
            "w0 {w0}, h {h}: residual {residual}"
        );
        let energy = |w: &V| 0.5 * w.dot(&i64_.component_mul(w));
        assert_close("|L|", i64_.component_mul(&b).norm(), l, 1e-5 * l);
        assert_close("energy", energy(&b), energy(&a), 1e-5 * energy(&a));
        assert!((b - a).norm() > 1e-3, "the spin changed");
    }
}

#[test]
fn velocity_integration_without_rotation_or_gravity_leaves_them_out() {
    let mut b = brick(Rot::from_euler_angles(0.3, 0.2, 0.1));
    b.angular_damping = 2.0;
    b.linear_damping = 3.0;
    let bodies = [b];
    let w = Vec3::new(1.0, 2.0, 0.5);
    let mut states = [BodyState::moving(Vec3::new(1.3, 0.0, 0.0), w)];
    integrate_velocities_with(&bodies, &mut states, None, false, 0.1);
    // No gravity, and the linear damping still acts: 1.3 / (1 + 0.1 * 3) = 1.
    assert_close("damped", states[0].linear_velocity.x.into(), 1.0, 1e-6);
    assert_eq!(states[0].linear_velocity.y, 0.0);
    assert_eq!(states[0].angular_velocity, w);
    integrate_velocities_with(&bodies, &mut states, Some(&gravity()), true, 0.1);
    // Gravity, then the damping: -g h / (1 + h c).
    assert_close(
        "gravity",
        states[0].linear_velocity.y.into(),
        f64::from(-G * 0.1) / 1.3,
        1e-6,
    );
    assert!(states[0].angular_velocity.norm() < w.norm() / 1.1, "damped");
}
