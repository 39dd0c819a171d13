//! The position feedback (soft and Baumgarte push-out, relax passes) and warm starting.

use super::*;
use crate::tests::{G, assert_close};

/// The overlap `depth` of a box on the floor (one point under its centre), no gravity, no warm
/// start: the velocity and displacement one step of `config` gives it.
fn push_out(depth: Real, config: &SolverConfig) -> (f64, f64) {
    let mut scene = OnFloor::new(1.0, 0.6, 0.0)
        .center_point()
        .at_height(0.5 - depth);
    let y0 = scene.bodies[1].pose.translation.y;
    scene.step(config, &Vec3::zeros(), &Effects::ALL);
    (
        scene.states[1].linear_velocity.y.into(),
        f64::from(scene.bodies[1].pose.translation.y - y0),
    )
}

#[test]
fn soft_push_out_follows_the_softness_formulas_and_relax_removes_its_velocity() {
    let h = f64::from(DT);
    let d: Real = 0.01;
    // A 5 Hz contact: the floor contact gets twice that (10 Hz), below the 15 Hz cap
    // (a quarter of the 60 Hz substep rate). One biased pass from rest gives the separation
    // speed mass_scale * bias_rate * depth.
    let (bias_rate, mass_scale, _) = soft(10.0, 1.0, h);
    let v = mass_scale * bias_rate * f64::from(d);
    let (vy, dy) = push_out(d, &one_substep(5.0, 0));
    assert_close("bias velocity", vy, v, 1e-5);
    assert_close("moved by it", dy, v * h, 1e-6);
    // The relax pass (rigid, no bias) takes that velocity away and keeps the displacement.
    let (vy, dy) = push_out(d, &one_substep(5.0, 1));
    assert!(vy.abs() < 1e-6, "relaxed velocity {vy}");
    assert_close("relaxed displacement", dy, v * h, 1e-6);
    // 60 Hz asked for: both the contact and the floor contact are capped at 15 Hz.
    let (bias_rate, mass_scale, _) = soft(15.0, 1.0, h);
    let (vy, _) = push_out(d, &one_substep(60.0, 0));
    assert_close(
        "capped stiffness",
        vy,
        mass_scale * bias_rate * f64::from(d),
        1e-5,
    );
    // A deep overlap asks for more than the push-out cap: the cap is the speed.
    let capped = SolverConfig {
        max_push_out: 1.5,
        ..one_substep(60.0, 0)
    };
    let (vy, _) = push_out(0.5, &capped);
    assert_close("push-out cap", vy, 1.5, 1e-5);
}

#[test]
fn baumgarte_push_out_is_beta_over_h_times_the_overlap_beyond_the_slop() {
    let config = SolverConfig {
        relax_iterations: 0,
        ..SolverConfig::baumgarte()
    };
    let (vy, _) = push_out(0.02, &config);
    // 0.2 * 60 * (0.02 - 0.005) = 0.18 m/s.
    assert_close("bias", vy, 0.18, 1e-5);
    // Within the slop nothing is corrected.
    let (vy, dy) = push_out(0.004, &config);
    assert!(vy.abs() < 1e-6 && dy.abs() < 1e-7, "{vy} {dy}");
}

#[test]
fn warm_starting_from_the_resting_impulses_is_at_rest_after_one_pass() {
    // By symmetry the resting solution of a cube on four corners is m g dt / 4 per corner.
    // Warm started with it, one pass finds nothing left to do; from zero, one Gauss-Seidel
    // pass over the four coupled corners leaves the box moving. Frictionless, so the pass is
    // one visit of the corners: with friction a patch's normal and tilt rows are solved again
    // after the friction rows (`solve_contact`), a second sweep that leaves only 9e-5 m/s.
    let residual = |warm: bool| {
        let mut scene = OnFloor::new(1.0, 0.0, 0.0);
        for imp in scene.contact.impulses.iter_mut() {
            imp.normal = G * DT / 4.0;
        }
        let config = SolverConfig {
            iterations: 1,
            warm_start: warm,
            ..SolverConfig::baumgarte()
        };
        scene.step(&config, &gravity(), &Effects::ALL);
        scene.states[1].linear_velocity.norm() + scene.states[1].angular_velocity.norm()
    };
    let warm = residual(true);
    let cold = residual(false);
    assert!(warm < 1e-5, "warm started residual {warm}");
    // From zero the one pass leaves a few percent of the substep's g dt = 0.16 m/s.
    assert!(cold > 1e-3, "cold started residual {cold}");
}

#[test]
fn without_warm_starting_the_carried_impulses_are_ignored() {
    let run = |impulse: Real| {
        let mut scene = OnFloor::new(1.0, 0.6, 0.0).moving(Vec3::new(0.5, -0.2, 0.0));
        for imp in scene.contact.impulses.iter_mut() {
            imp.normal = impulse;
            imp.friction = Vec3::new(impulse, 0.0, 0.0);
        }
        scene.contact.tilt_impulse = Vec3::new(impulse, 0.0, 0.0);
        let config = SolverConfig {
            warm_start: false,
            ..SolverConfig::default()
        };
        scene.step(&config, &gravity(), &Effects::ALL);
        (scene.states, scene.contact)
    };
    assert_eq!(run(0.0), run(50.0));
}
