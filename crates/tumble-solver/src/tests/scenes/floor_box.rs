//! A box resting on the floor, sliding on it, bouncing off it, falling onto it from above.

use super::*;
use crate::tests::{G, assert_close};

#[test]
fn a_resting_box_carries_its_weight_each_substep_at_the_soft_contact_depth() {
    let mass = 2.0;
    let mut scene = OnFloor::new(mass, 0.6, 0.0);
    let config = SolverConfig::default();
    scene.run(&config, &Effects::ALL, 120);
    let contact = &scene.contact;
    let h = DT / config.substeps as Real;
    // The stored impulses are the last substep's: together they hold m g h.
    let per_substep: Real = contact.impulses.iter().map(|i| i.normal).sum();
    assert_close(
        "impulse per substep",
        per_substep.into(),
        (mass * G * h).into(),
        0.01 * f64::from(mass * G * h),
    );
    let per_step: Real = contact.total_normal_impulse.iter().sum();
    assert_close(
        "impulse per step",
        per_step.into(),
        (mass * G * DT).into(),
        0.01 * f64::from(mass * G * DT),
    );
    // Settled, a substep's biased pass moves the box by -(mass_scale bias_rate s +
    // impulse_scale g h) h = 0, so s = -g h impulse_scale / (mass_scale bias_rate) = -g /
    // omega^2: the static contact at its hertz, min(2 * 60, 360 / 4) = 90 Hz, sinks 31 um.
    let omega = 2.0 * std::f64::consts::PI * 90.0;
    assert_close(
        "settled depth",
        scene.depth(),
        f64::from(G) / (omega * omega),
        3e-6,
    );
    let p = scene.bodies[1].pose.translation.vector;
    assert!(p.x.abs() < 1e-5 && p.z.abs() < 1e-5, "drifted to {p}");
    assert!(scene.bodies[1].pose.rotation.angle() < 1e-4, "tilted");
}

#[test]
fn baumgarte_removes_a_fifth_of_the_overlap_beyond_the_slop_per_step() {
    // A rigid PGS contact with bias beta / h (depth - slop) moves the box out by exactly
    // beta (depth - slop) per step, so the excess over the slop decays as 0.8^n and the box
    // settles at the slop, never deeper.
    let d0: Real = 0.02;
    let mut scene = OnFloor::new(1.0, 0.6, 0.0).at_height(0.5 - d0);
    let config = SolverConfig::baumgarte();
    let slop = f64::from(config.slop);
    for n in 1..=6 {
        scene.run(&config, &Effects::ALL, 1);
        let want = slop + (f64::from(d0) - slop) * 0.8f64.powi(n);
        // The rigid rows converge to f32 round-off in 60 passes; 2e-6 m is ~30 ulp at 0.5 m.
        assert_close(&format!("depth after {n} steps"), scene.depth(), want, 2e-6);
    }
    scene.run(&config, &Effects::ALL, 120);
    assert_close("settled depth", scene.depth(), slop, 2e-6);
}

#[test]
fn a_sliding_box_is_decelerated_at_mu_g_by_friction_at_the_coulomb_limit() {
    let mu = 0.5;
    let v0: Real = 4.0;
    let mut scene = OnFloor::new(1.0, mu, 0.0).moving(Vec3::new(v0, 0.0, 0.0));
    // Rigid rows, converged: the floor carries m g dt and every point slides, so each
    // point's friction impulse sits on its Coulomb limit mu * normal impulse.
    let config = SolverConfig::baumgarte();
    scene.run(&config, &Effects::ALL, 1);
    let dv = f64::from(mu * G * DT);
    // 1% of the velocity change.
    assert_close(
        "vx after one step",
        scene.states[1].linear_velocity.x.into(),
        f64::from(v0) - dv,
        0.01 * dv,
    );
    for imp in &scene.contact.impulses[..4] {
        assert_close(
            "friction on the Coulomb limit",
            imp.friction.norm().into(),
            f64::from(mu * imp.normal),
            1e-6,
        );
        // Friction opposes the sliding (+x).
        assert!(
            imp.friction.x < 0.0 && imp.friction.normalize().x < -0.999,
            "{}",
            imp.friction
        );
    }
}

#[test]
fn a_sliding_box_stops_after_v0_squared_over_2_mu_g_and_stays() {
    let mu = 0.5;
    let v0: Real = 2.0;
    let mut scene = OnFloor::new(1.0, mu, 0.0).moving(Vec3::new(v0, 0.0, 0.0));
    let config = SolverConfig::default();
    scene.run(&config, &Effects::ALL, 15);
    // v = v0 - mu g t while sliding; t = 0.25 s. The soft normal carries the weight on
    // average, so the friction impulse sums to mu m g t up to the small vertical settling.
    let t = 15.0 * DT;
    assert_close(
        "v at 0.25 s",
        scene.states[1].linear_velocity.x.into(),
        f64::from(v0 - mu * G * t),
        0.01,
    );
    scene.run(&config, &Effects::ALL, 45);
    // It stopped at 0.41 s; static friction holds it since.
    let v = scene.states[1].linear_velocity;
    assert!(v.norm() < 1e-3, "{v}");
    let distance = f64::from(v0 * v0 / (2.0 * mu * G));
    // The discrete integration differs from the continuous distance by about v0 h / 2 = 3 mm.
    assert_close(
        "stopping distance",
        scene.bodies[1].pose.translation.x.into(),
        distance,
        0.01,
    );
}

#[test]
fn with_friction_off_a_rough_box_slides_freely_and_stale_friction_is_not_reapplied() {
    let v0 = Vec3::new(3.0, 0.0, -1.0);
    let mut scene = OnFloor::new(1.0, 0.8, 0.0).moving(v0);
    for imp in scene.contact.impulses.iter_mut() {
        imp.normal = 1.0 * G * DT / 4.0;
        imp.friction = Vec3::new(-0.5, 0.0, 0.2);
    }
    let effects = Effects {
        friction: false,
        ..Effects::ALL
    };
    scene.run(&SolverConfig::default(), &effects, 10);
    let v = scene.states[1].linear_velocity;
    // Only normal (vertical) impulses act: the horizontal velocity is untouched.
    assert!(
        (v.x - v0.x).abs() < 1e-5 && (v.z - v0.z).abs() < 1e-5,
        "{v}"
    );
    assert!(
        scene
            .contact
            .impulses
            .iter()
            .all(|i| i.friction == Vec3::zeros())
    );
}

/// A box falling at `speed` onto the floor, touching it at the start of the step, one point
/// under its centre (so the restitution pass is exact in one sweep); `gap` above it.
fn drop_once(
    speed: Real,
    restitution: Real,
    config: &SolverConfig,
    effects: &Effects,
    gap: Real,
) -> OnFloor {
    let mut scene = OnFloor::new(1.0, 0.6, restitution)
        .center_point()
        .at_height(0.5 + gap)
        .moving(Vec3::new(0.0, -speed, 0.0));
    scene.step(config, &gravity(), effects);
    scene
}

/// The box's vertical velocity after [`drop_once`] from touching the floor.
fn rebound(speed: Real, config: &SolverConfig, effects: &Effects) -> f64 {
    drop_once(speed, 0.5, config, effects, 0.0).states[1]
        .linear_velocity
        .y
        .into()
}

#[test]
fn restitution_returns_e_times_the_approach_speed_above_the_threshold_only() {
    for config in [SolverConfig::default(), SolverConfig::baumgarte()] {
        // 4 m/s at e = 0.5 (the floor's 0 and the box's 0.5 mix to the larger): 2 m/s up.
        assert_close("rebound", rebound(4.0, &config, &Effects::ALL), 2.0, 1e-5);
        // 1.5 m/s is above the 1 m/s threshold: 0.75 m/s up.
        let v = rebound(1.5, &config, &Effects::ALL);
        assert_close("rebound above threshold", v, 0.75, 1e-5);
        // Exactly at the threshold counts (only speeds below it are ignored).
        let v = rebound(1.0, &config, &Effects::ALL);
        assert_close("rebound at the threshold", v, 0.5, 1e-5);
        // 0.5 m/s is below it: the box stays (the relax or last pass leaves it at rest).
        let v = rebound(0.5, &config, &Effects::ALL);
        assert!(v.abs() < 1e-4, "{:?}: {v}", config.kind);
        // The restitution effect off: no rebound at any speed.
        let off = Effects {
            restitution: false,
            ..Effects::ALL
        };
        let v = rebound(4.0, &config, &off);
        assert!(v.abs() < 1e-4, "{v}");
    }
}

#[test]
fn a_speculative_point_that_never_pushed_gives_no_rebound() {
    // One metre above the floor at 4 m/s the box does not reach it this step: the point is
    // speculative, pushes nothing, and restitution leaves the free fall alone.
    let scene = drop_once(4.0, 0.5, &SolverConfig::default(), &Effects::ALL, 1.0);
    assert_eq!(scene.contact.total_normal_impulse[0], 0.0);
    assert_close(
        "free fall",
        scene.states[1].linear_velocity.y.into(),
        f64::from(-4.0 - G * DT),
        1e-5,
    );
}

#[test]
fn a_fast_box_stops_exactly_at_the_speculative_gap() {
    // Baumgarte, one substep, no relax: the speculative row lets the box approach by the
    // gap s in the step, so it leaves with -s / dt and lands exactly on the floor.
    let gap: Real = 0.1;
    let scene = drop_once(30.0, 0.0, &SolverConfig::baumgarte(), &Effects::ALL, gap);
    assert_close(
        "approach speed",
        scene.states[1].linear_velocity.y.into(),
        f64::from(-gap / DT),
        1e-3,
    );
    assert!(scene.contact.total_normal_impulse[0] > 0.0);
    assert_close(
        "lands on the floor",
        scene.bodies[1].pose.translation.y.into(),
        0.5,
        2e-6,
    );
}
