//! Closed-form cases through the whole solve stage: a box resting on a fixed floor, sliding
//! on it, bouncing, falling onto it from above; two boxes colliding head on; the soft and
//! Baumgarte position feedback; relax passes; warm starting; the visiting order.

use tumble_geometry::{Point3, Pose, Real, Vec3};

use super::{
    DT, G, assert_close, floor, floor_center, floor_corners, gravity, manifold, material, unit_cube,
};
use crate::{
    Body, BodyKind, BodyState, Coloring, Contact, Effects, SolveOrder, SolveStats, SolverConfig,
    color_constraints, finalize_bodies, solve, solve_with_effects,
};

/// One step of `contacts` over `bodies`, colored greedily, then the poses are written.
fn step(
    bodies: &mut [Body],
    states: &mut [BodyState],
    contacts: &mut [Contact],
    config: &SolverConfig,
    gravity: &Vec3,
    effects: &Effects,
) -> SolveStats {
    let pairs: Vec<(u32, u32)> = contacts.iter().map(|c| (c.body_a, c.body_b)).collect();
    let dynamic: Vec<bool> = bodies.iter().map(Body::is_dynamic).collect();
    let coloring = color_constraints(&pairs, &dynamic);
    let stats = solve_with_effects(
        bodies, states, contacts, &coloring, config, DT, gravity, effects,
    );
    finalize_bodies(bodies, states);
    stats
}

/// A box on the floor for `steps` steps, its manifold rebuilt each step by `geometry` (same
/// ids, so the impulses carry over as a cache hit would carry them).
fn on_floor(
    bodies: &mut [Body; 2],
    states: &mut [BodyState; 2],
    contact: &mut Contact,
    config: &SolverConfig,
    effects: &Effects,
    steps: usize,
    geometry: fn(&Body) -> tumble_geometry::Manifold,
) {
    for _ in 0..steps {
        contact.manifold = geometry(&bodies[1]);
        let mut contacts = [*contact];
        step(bodies, states, &mut contacts, config, &gravity(), effects);
        *contact = contacts[0];
    }
}

fn resting_box(mass: Real, friction: Real, restitution: Real) -> [Body; 2] {
    let m = material(friction, restitution);
    [
        floor(m),
        unit_cube(mass, Pose::translation(0.0, 0.5, 0.0), m),
    ]
}

/// The soft-step coefficients of the documented formulas, in f64: `(bias_rate, mass_scale,
/// impulse_scale)` for `hertz`, damping ratio `zeta` and substep `h`.
fn soft(hertz: f64, zeta: f64, h: f64) -> (f64, f64, f64) {
    let omega = 2.0 * std::f64::consts::PI * hertz;
    let a1 = 2.0 * zeta + h * omega;
    let a2 = h * omega * a1;
    (omega / a1, a2 / (1.0 + a2), 1.0 / (1.0 + a2))
}

#[test]
fn a_resting_box_carries_its_weight_each_substep_at_the_soft_contact_depth() {
    let mass = 2.0;
    let mut bodies = resting_box(mass, 0.6, 0.0);
    let mut states = [BodyState::default(); 2];
    let mut contact = Contact::new(0, 1, floor_corners(&bodies[1]));
    let config = SolverConfig::default();
    on_floor(
        &mut bodies,
        &mut states,
        &mut contact,
        &config,
        &Effects::ALL,
        120,
        floor_corners,
    );
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
    let depth = 0.5 - f64::from(bodies[1].pose.translation.y);
    assert_close("settled depth", depth, f64::from(G) / (omega * omega), 3e-6);
    let p = bodies[1].pose.translation.vector;
    assert!(p.x.abs() < 1e-5 && p.z.abs() < 1e-5, "drifted to {p}");
    assert!(bodies[1].pose.rotation.angle() < 1e-4, "tilted");
}

#[test]
fn baumgarte_removes_a_fifth_of_the_overlap_beyond_the_slop_per_step() {
    // A rigid PGS contact with bias beta / h (depth - slop) moves the box out by exactly
    // beta (depth - slop) per step, so the excess over the slop decays as 0.8^n and the box
    // settles at the slop, never deeper.
    let mut bodies = resting_box(1.0, 0.6, 0.0);
    let d0: Real = 0.02;
    bodies[1].pose = Pose::translation(0.0, 0.5 - d0, 0.0);
    let mut states = [BodyState::default(); 2];
    let mut contact = Contact::new(0, 1, floor_corners(&bodies[1]));
    let config = SolverConfig::baumgarte();
    let slop = f64::from(config.slop);
    for n in 1..=6 {
        on_floor(
            &mut bodies,
            &mut states,
            &mut contact,
            &config,
            &Effects::ALL,
            1,
            floor_corners,
        );
        let depth = 0.5 - f64::from(bodies[1].pose.translation.y);
        let want = slop + (f64::from(d0) - slop) * 0.8f64.powi(n);
        // The rigid rows converge to f32 round-off in 60 passes; 2e-6 m is ~30 ulp at 0.5 m.
        assert_close(&format!("depth after {n} steps"), depth, want, 2e-6);
    }
    on_floor(
        &mut bodies,
        &mut states,
        &mut contact,
        &config,
        &Effects::ALL,
        120,
        floor_corners,
    );
    let depth = 0.5 - f64::from(bodies[1].pose.translation.y);
    assert_close("settled depth", depth, slop, 2e-6);
}

#[test]
fn a_sliding_box_is_decelerated_at_mu_g_by_friction_at_the_coulomb_limit() {
    let mu = 0.5;
    let mut bodies = resting_box(1.0, mu, 0.0);
    let v0: Real = 4.0;
    let mut states = [
        BodyState::default(),
        BodyState::moving(Vec3::new(v0, 0.0, 0.0), Vec3::zeros()),
    ];
    let mut contact = Contact::new(0, 1, floor_corners(&bodies[1]));
    // Rigid rows, converged: the floor carries m g dt and every point slides, so each
    // point's friction impulse sits on its Coulomb limit mu * normal impulse.
    let config = SolverConfig::baumgarte();
    on_floor(
        &mut bodies,
        &mut states,
        &mut contact,
        &config,
        &Effects::ALL,
        1,
        floor_corners,
    );
    let dv = f64::from(mu * G * DT);
    // 1% of the velocity change.
    assert_close(
        "vx after one step",
        states[1].linear_velocity.x.into(),
        f64::from(v0) - dv,
        0.01 * dv,
    );
    for i in 0..4 {
        let imp = contact.impulses[i];
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
    let mut bodies = resting_box(1.0, mu, 0.0);
    let mut states = [
        BodyState::default(),
        BodyState::moving(Vec3::new(v0, 0.0, 0.0), Vec3::zeros()),
    ];
    let mut contact = Contact::new(0, 1, floor_corners(&bodies[1]));
    let config = SolverConfig::default();
    on_floor(
        &mut bodies,
        &mut states,
        &mut contact,
        &config,
        &Effects::ALL,
        15,
        floor_corners,
    );
    // v = v0 - mu g t while sliding; t = 0.25 s. The soft normal carries the weight on
    // average, so the friction impulse sums to mu m g t up to the small vertical settling.
    let t = 15.0 * DT;
    assert_close(
        "v at 0.25 s",
        states[1].linear_velocity.x.into(),
        f64::from(v0 - mu * G * t),
        0.01,
    );
    on_floor(
        &mut bodies,
        &mut states,
        &mut contact,
        &config,
        &Effects::ALL,
        45,
        floor_corners,
    );
    // It stopped at 0.41 s; static friction holds it since.
    assert!(
        states[1].linear_velocity.norm() < 1e-3,
        "{}",
        states[1].linear_velocity
    );
    let distance = f64::from(v0 * v0 / (2.0 * mu * G));
    // The discrete integration differs from the continuous distance by about v0 h / 2 = 3 mm.
    assert_close(
        "stopping distance",
        bodies[1].pose.translation.x.into(),
        distance,
        0.01,
    );
}

#[test]
fn with_friction_off_a_rough_box_slides_freely_and_stale_friction_is_not_reapplied() {
    let mut bodies = resting_box(1.0, 0.8, 0.0);
    let v0 = Vec3::new(3.0, 0.0, -1.0);
    let mut states = [BodyState::default(), BodyState::moving(v0, Vec3::zeros())];
    let mut contact = Contact::new(0, 1, floor_corners(&bodies[1]));
    for imp in contact.impulses.iter_mut() {
        imp.normal = 1.0 * G * DT / 4.0;
        imp.friction = Vec3::new(-0.5, 0.0, 0.2);
    }
    let effects = Effects {
        friction: false,
        ..Effects::ALL
    };
    on_floor(
        &mut bodies,
        &mut states,
        &mut contact,
        &SolverConfig::default(),
        &effects,
        10,
        floor_corners,
    );
    let v = states[1].linear_velocity;
    // Only normal (vertical) impulses act: the horizontal velocity is untouched.
    assert!(
        (v.x - v0.x).abs() < 1e-5 && (v.z - v0.z).abs() < 1e-5,
        "{v}"
    );
    assert!(contact.impulses.iter().all(|i| i.friction == Vec3::zeros()));
}

/// A box falling at `speed` onto the floor, touching it at the start of the step, one point
/// under its centre (so the restitution pass is exact in one sweep).
fn drop_once(
    speed: Real,
    restitution: Real,
    config: &SolverConfig,
    effects: &Effects,
    gap: Real,
) -> (BodyState, Contact) {
    let mut bodies = resting_box(1.0, 0.6, restitution);
    bodies[1].pose = Pose::translation(0.0, 0.5 + gap, 0.0);
    let mut states = [
        BodyState::default(),
        BodyState::moving(Vec3::new(0.0, -speed, 0.0), Vec3::zeros()),
    ];
    let mut contacts = [Contact::new(0, 1, floor_center(&bodies[1]))];
    step(
        &mut bodies,
        &mut states,
        &mut contacts,
        config,
        &gravity(),
        effects,
    );
    (states[1], contacts[0])
}

#[test]
fn restitution_returns_e_times_the_approach_speed_above_the_threshold_only() {
    for config in [SolverConfig::default(), SolverConfig::baumgarte()] {
        // 4 m/s at e = 0.5 (the floor's 0 and the box's 0.5 mix to the larger): 2 m/s up.
        let (s, _) = drop_once(4.0, 0.5, &config, &Effects::ALL, 0.0);
        assert_close("rebound", s.linear_velocity.y.into(), 2.0, 1e-5);
        // 1.5 m/s is above the 1 m/s threshold: 0.75 m/s up.
        let (s, _) = drop_once(1.5, 0.5, &config, &Effects::ALL, 0.0);
        assert_close(
            "rebound above threshold",
            s.linear_velocity.y.into(),
            0.75,
            1e-5,
        );
        // Exactly at the threshold counts (only speeds below it are ignored).
        let (s, _) = drop_once(1.0, 0.5, &config, &Effects::ALL, 0.0);
        assert_close(
            "rebound at the threshold",
            s.linear_velocity.y.into(),
            0.5,
            1e-5,
        );
        // 0.5 m/s is below it: the box stays (the relax or last pass leaves it at rest).
        let (s, _) = drop_once(0.5, 0.5, &config, &Effects::ALL, 0.0);
        assert!(
            s.linear_velocity.y.abs() < 1e-4,
            "{:?}: {}",
            config.kind,
            s.linear_velocity.y
        );
        // The restitution effect off: no rebound at any speed.
        let off = Effects {
            restitution: false,
            ..Effects::ALL
        };
        let (s, _) = drop_once(4.0, 0.5, &config, &off, 0.0);
        assert!(s.linear_velocity.y.abs() < 1e-4, "{}", s.linear_velocity.y);
    }
}

#[test]
fn a_speculative_point_that_never_pushed_gives_no_rebound() {
    // One metre above the floor at 4 m/s the box does not reach it this step: the point is
    // speculative, pushes nothing, and restitution leaves the free fall alone.
    let (s, contact) = drop_once(4.0, 0.5, &SolverConfig::default(), &Effects::ALL, 1.0);
    assert_eq!(contact.total_normal_impulse[0], 0.0);
    assert_close(
        "free fall",
        s.linear_velocity.y.into(),
        f64::from(-4.0 - G * DT),
        1e-5,
    );
}

#[test]
fn a_fast_box_stops_exactly_at_the_speculative_gap() {
    // Baumgarte, one substep, no relax: the speculative row lets the box approach by the
    // gap s in the step, so it leaves with -s / dt and lands exactly on the floor.
    let gap: Real = 0.1;
    let (s, contact) = drop_once(30.0, 0.0, &SolverConfig::baumgarte(), &Effects::ALL, gap);
    assert_close(
        "approach speed",
        s.linear_velocity.y.into(),
        f64::from(-gap / DT),
        1e-3,
    );
    assert!(contact.total_normal_impulse[0] > 0.0);
    let mut bodies = resting_box(1.0, 0.6, 0.0);
    bodies[1].pose = Pose::translation(0.0, 0.5 + gap, 0.0);
    let mut states = [
        BodyState::default(),
        BodyState::moving(Vec3::new(0.0, -30.0, 0.0), Vec3::zeros()),
    ];
    let mut contacts = [Contact::new(0, 1, floor_center(&bodies[1]))];
    step(
        &mut bodies,
        &mut states,
        &mut contacts,
        &SolverConfig::baumgarte(),
        &gravity(),
        &Effects::ALL,
    );
    assert_close(
        "lands on the floor",
        bodies[1].pose.translation.y.into(),
        0.5,
        2e-6,
    );
}

/// Two boxes on the x axis, A (density `ma`) moving at `v` toward B (density `mb`) at rest,
/// touching at x = 0.5 through one point on the line of centres, no gravity.
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
    step(
        &mut bodies,
        &mut states,
        &mut contacts,
        config,
        &Vec3::zeros(),
        &Effects::ALL,
    );
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
        let pusher = super::body(
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
        step(
            &mut bodies,
            &mut states,
            &mut contacts,
            &config,
            &Vec3::zeros(),
            &Effects::ALL,
        );
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
fn push_out(depth: Real, config: &SolverConfig) -> (f64, f64) {
    let mut bodies = resting_box(1.0, 0.6, 0.0);
    bodies[1].pose = Pose::translation(0.0, 0.5 - depth, 0.0);
    let mut states = [BodyState::default(); 2];
    let mut contacts = [Contact::new(0, 1, floor_center(&bodies[1]))];
    let y0 = bodies[1].pose.translation.y;
    step(
        &mut bodies,
        &mut states,
        &mut contacts,
        config,
        &Vec3::zeros(),
        &Effects::ALL,
    );
    (
        states[1].linear_velocity.y.into(),
        f64::from(bodies[1].pose.translation.y - y0),
    )
}

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
    step(
        &mut bodies,
        &mut states,
        &mut contacts,
        &one_substep(5.0, 0),
        &Vec3::zeros(),
        &Effects::ALL,
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
    // pass over the four coupled corners leaves the box moving.
    let residual = |warm: bool| {
        let mut bodies = resting_box(1.0, 0.6, 0.0);
        let mut states = [BodyState::default(); 2];
        let mut contacts = [Contact::new(0, 1, floor_corners(&bodies[1]))];
        for imp in contacts[0].impulses.iter_mut() {
            imp.normal = G * DT / 4.0;
        }
        let config = SolverConfig {
            iterations: 1,
            warm_start: warm,
            ..SolverConfig::baumgarte()
        };
        step(
            &mut bodies,
            &mut states,
            &mut contacts,
            &config,
            &gravity(),
            &Effects::ALL,
        );
        states[1].linear_velocity.norm() + states[1].angular_velocity.norm()
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
        let mut bodies = resting_box(1.0, 0.6, 0.0);
        let mut states = [
            BodyState::default(),
            BodyState::moving(Vec3::new(0.5, -0.2, 0.0), Vec3::zeros()),
        ];
        let mut contacts = [Contact::new(0, 1, floor_corners(&bodies[1]))];
        for imp in contacts[0].impulses.iter_mut() {
            imp.normal = impulse;
            imp.friction = Vec3::new(impulse, 0.0, 0.0);
        }
        contacts[0].tilt_impulse = Vec3::new(impulse, 0.0, 0.0);
        let config = SolverConfig {
            warm_start: false,
            ..SolverConfig::default()
        };
        step(
            &mut bodies,
            &mut states,
            &mut contacts,
            &config,
            &gravity(),
            &Effects::ALL,
        );
        (states, contacts)
    };
    assert_eq!(run(0.0), run(50.0));
}

/// A column of `n` unit cubes on the floor: contact k joins cube k (or the floor) and k + 1.
fn column(n: usize) -> (Vec<Body>, Vec<BodyState>, Vec<Contact>) {
    let m = material(0.6, 0.0);
    let mut bodies = vec![floor(m)];
    let mut contacts = Vec::new();
    for k in 0..n {
        // Slightly sunk and moving, so every contact has work to do.
        let cube = unit_cube(
            1.0,
            Pose::new(
                Vec3::new(0.0, 0.49 + k as Real * 0.99, 0.0),
                Vec3::new(0.0, 0.0, 0.02 * k as Real),
            ),
            m,
        );
        let mut mf = floor_corners(&cube);
        for p in mf.contacts.iter_mut() {
            p.depth += k as Real * 0.99;
            p.position.y += 0.5 * k as Real * 0.99;
        }
        contacts.push(Contact::new(k as u32, k as u32 + 1, mf));
        bodies.push(cube);
    }
    let states = (0..=n)
        .map(|k| {
            if k == 0 {
                BodyState::default()
            } else {
                BodyState::moving(Vec3::new(0.1, -0.5, 0.0), Vec3::zeros())
            }
        })
        .collect();
    (bodies, states, contacts)
}

#[test]
fn the_colored_order_is_the_sequential_order_of_the_permuted_contacts() {
    let (bodies, states0, contacts0) = column(4);
    let pairs: Vec<(u32, u32)> = contacts0.iter().map(|c| (c.body_a, c.body_b)).collect();
    let dynamic: Vec<bool> = bodies.iter().map(Body::is_dynamic).collect();
    let coloring = color_constraints(&pairs, &dynamic);
    // A column alternates two colors: contacts 0, 2 then 1, 3.
    assert_eq!(coloring.order, vec![0, 2, 1, 3]);
    let run = |contacts: &[Contact], coloring: &Coloring, order: SolveOrder| {
        let (mut states, mut contacts) = (states0.clone(), contacts.to_vec());
        let config = SolverConfig {
            order,
            ..SolverConfig::default()
        };
        solve(
            &bodies,
            &mut states,
            &mut contacts,
            coloring,
            &config,
            DT,
            &gravity(),
        );
        (states, contacts)
    };
    let permuted: Vec<Contact> = coloring
        .order
        .iter()
        .map(|&i| contacts0[i as usize])
        .collect();
    let (colored_states, colored_contacts) = run(&contacts0, &coloring, SolveOrder::Colored);
    let (permuted_states, permuted_contacts) =
        run(&permuted, &Coloring::default(), SolveOrder::Sequential);
    assert_eq!(colored_states, permuted_states);
    for (k, &i) in coloring.order.iter().enumerate() {
        assert_eq!(colored_contacts[i as usize], permuted_contacts[k]);
    }
    // The order matters for Gauss-Seidel, so the comparisons above can tell orders apart.
    let (sequential_states, _) = run(&contacts0, &Coloring::default(), SolveOrder::Sequential);
    assert_ne!(sequential_states, colored_states);
    // Sequential ignores a coloring; Colored falls back to sequential for a coloring of
    // other constraints.
    assert_eq!(
        run(&contacts0, &coloring, SolveOrder::Sequential).0,
        sequential_states
    );
    let stale = color_constraints(&pairs[..2], &dynamic);
    assert_eq!(
        run(&contacts0, &stale, SolveOrder::Colored).0,
        sequential_states
    );
}

#[test]
fn solve_stats_count_constraints_points_and_parallel_colors_only() {
    // A dynamic hub touched by 30 dynamic boxes: 24 colors of one constraint each, and the
    // last 6 in the overflow set, which never runs in parallel.
    let m = material(0.5, 0.0);
    let mut bodies = vec![unit_cube(1.0, Pose::identity(), m)];
    let mut contacts = Vec::new();
    for k in 0..30 {
        let angle = k as Real * 0.2;
        let dir = Vec3::new(angle.cos(), 0.0, angle.sin());
        bodies.push(unit_cube(1.0, Pose::translation(dir.x, 0.0, dir.z), m));
        let point = Point3::from(dir * 0.5);
        let points: Vec<(Point3, Real, u32)> =
            (0..(k % 4 + 1)).map(|id| (point, 0.01, id)).collect();
        contacts.push(Contact::new(0, k + 1, manifold(dir, &points)));
    }
    let states = vec![BodyState::moving(Vec3::new(0.0, 0.0, 0.0), Vec3::zeros()); 31];
    let pairs: Vec<(u32, u32)> = contacts.iter().map(|c| (c.body_a, c.body_b)).collect();
    let dynamic = vec![true; 31];
    let coloring = color_constraints(&pairs, &dynamic);
    assert_eq!(coloring.overflow_count(), 6);
    let run = |threshold: u32| {
        let (mut states, mut contacts) = (states.clone(), contacts.clone());
        let config = SolverConfig {
            parallel_threshold: threshold,
            ..SolverConfig::default()
        };
        let stats = solve(
            &bodies,
            &mut states,
            &mut contacts,
            &coloring,
            &config,
            DT,
            &Vec3::zeros(),
        );
        (stats, states)
    };
    let (wide, wide_states) = run(1);
    let points: usize = (0..30).map(|k| k % 4 + 1).sum();
    assert_eq!(
        wide,
        SolveStats {
            constraints: 30,
            points,
            parallel_batches: 24
        }
    );
    let (narrow, narrow_states) = run(2);
    assert_eq!(narrow.parallel_batches, 0);
    // The overflow set shares the hub: it is solved one constraint after another either way.
    assert_eq!(wide_states, narrow_states);
    assert!(
        narrow_states[0].linear_velocity.norm() > 0.0
            || narrow_states[1].linear_velocity.norm() > 0.0
    );
}

#[test]
fn a_step_with_gravity_off_or_rotation_off_leaves_that_motion_out() {
    let m = material(0.5, 0.0);
    let mut cube = unit_cube(1.0, Pose::translation(0.0, 5.0, 0.0), m);
    cube.angular_damping = 3.0;
    let w0 = Vec3::new(0.0, 2.0, 0.0);
    let run = |effects: &Effects| {
        let mut bodies = [cube];
        let mut states = [BodyState::moving(Vec3::zeros(), w0)];
        step(
            &mut bodies,
            &mut states,
            &mut [],
            &SolverConfig::default(),
            &gravity(),
            effects,
        );
        (bodies[0], states[0])
    };
    let (_, all) = run(&Effects::ALL);
    assert_close(
        "falls",
        all.linear_velocity.y.into(),
        f64::from(-G * DT),
        1e-5,
    );
    // Angular damping 3/s over 6 substeps of 1/360 s: w0 / (1 + 3/360)^6.
    assert_close(
        "damped spin",
        all.angular_velocity.y.into(),
        2.0 / (1.0f64 + 3.0 / 360.0).powi(6),
        1e-5,
    );
    let (_, no_gravity) = run(&Effects {
        gravity: false,
        ..Effects::ALL
    });
    assert_eq!(no_gravity.linear_velocity, Vec3::zeros());
    // Rotation off: no body turns, whatever spin it had.
    let (b, no_rotation) = run(&Effects {
        rotation: false,
        ..Effects::ALL
    });
    assert_eq!(no_rotation.angular_velocity, Vec3::zeros());
    assert_eq!(b.pose.rotation, cube.pose.rotation);
}
