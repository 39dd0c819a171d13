//! Tumble against rapier3d on the same canonical scenes.
//!
//! Both engines build each scene from the same `tumble-scenes` data (sizes, masses, materials,
//! time step) and run it for the scene's 10 s (600 steps at 60 Hz) at matched substeps:
//! Tumble's default soft step with 6 substeps (`tumble_solver::DEFAULT_SUBSTEPS`) against
//! rapier's 6 solver iterations, which in rapier's soft-step solver are substeps too. For each
//! resting structure the test asserts, with bounds from the measured figures (see [`Bounds`]):
//!
//! - Tumble's horizontal creep at every step stays under an absolute bound, and is no more
//!   than rapier's, whose own creep is pinned by an absolute bound too, so the comparison
//!   cannot loosen when the reference creeps more;
//! - the ratio of the engines' sag (how far the structure settles) lies between the ratios of
//!   their contact stiffnesses, which are known (see [`sag_ratio_range`]), and within 10% of
//!   its measured value for the scene; for the column, each engine's sag matches the spring
//!   model of its contacts (see [`column_sag`]);
//! - the engines' final positions, body by body, agree within a bound: sideways tightly, in
//!   3D within the sag difference the stiffness explains.
//!
//! A last test drops a box on the floor and compares the heights at which the two engines let
//! it rest.
//!
//! Run time on 2 cores: about 30 s for the file while other builds share the cores, 18 s of
//! CPU time (`cargo test -p tumble-tests --test vs_rapier -- --nocapture` prints the figures).
//! The 650-cube pyramid is nearly all of it, most of that Tumble's 600 steps; the column, the
//! wall and the dropped box take a few seconds together.

use tumble::prelude::*;
use tumble_scenes::builders::common::{floor, unit_cube};
use tumble_scenes::{RapierOptions, Scene, build_rapier_with, pyramid, stack, wall};
use tumble_tests::scene_support::horizontal_drift;

/// One engine's run of one scene.
struct Outcome {
    /// Final centre of every body, in scene order.
    positions: Vec<[f32; 3]>,
    /// Largest horizontal displacement of any dynamic body from its start at any step, m.
    drift: f32,
    /// Largest drop of any dynamic body's centre below its start at the end, m.
    sag: f32,
}

/// The largest drop of any dynamic body's centre below its scene position.
fn sag(scene: &Scene, positions: &[[f32; 3]]) -> f32 {
    scene
        .bodies
        .iter()
        .zip(positions)
        .filter(|(spec, _)| spec.is_dynamic())
        .map(|(spec, p)| spec.position[1] - p[1])
        .fold(0.0, f32::max)
}

/// Tumble's default configuration (soft step, 6 substeps, CPU) with every body awake.
fn tumble_config() -> WorldConfig {
    WorldConfig {
        effects: tumble::EffectOverrides::NO_SLEEP,
        ..WorldConfig::default()
    }
}

/// Rapier with as many solver iterations (substeps of its soft-step solver) as Tumble's
/// default has substeps; no sleeping, so both engines integrate every body every step.
fn rapier_options() -> RapierOptions {
    RapierOptions {
        solver_iterations: tumble_config().solver.substeps as usize,
        sleep: false,
        ccd: false,
    }
}

/// Runs `steps` steps of `step`, reading every body's centre with `positions` after each, and
/// keeps the worst drift and the final state.
fn run(
    scene: &Scene,
    steps: u32,
    mut step: impl FnMut(),
    positions: impl Fn() -> Vec<[f32; 3]>,
) -> Outcome {
    let mut drift = 0.0f32;
    for _ in 0..steps {
        step();
        drift = drift.max(horizontal_drift(scene, &positions()));
    }
    let positions = positions();
    assert!(
        positions.iter().flatten().all(|x| x.is_finite()),
        "{}: a non-finite position",
        scene.name
    );
    Outcome {
        drift,
        sag: sag(scene, &positions),
        positions,
    }
}

fn run_tumble(scene: &Scene, steps: u32) -> Outcome {
    let (world, handles) =
        World::from_scene(scene, tumble_config()).expect("canonical scenes are valid");
    let world = std::cell::RefCell::new(world);
    run(
        scene,
        steps,
        || world.borrow_mut().step().expect("a valid world steps"),
        || {
            let world = world.borrow();
            handles
                .iter()
                .map(|&h| {
                    world
                        .pose(h)
                        .expect("live handle")
                        .translation
                        .vector
                        .into()
                })
                .collect()
        },
    )
}

fn run_rapier(scene: &Scene, steps: u32) -> Outcome {
    let world = std::cell::RefCell::new(build_rapier_with(scene, &rapier_options()));
    run(
        scene,
        steps,
        || world.borrow_mut().step(),
        || {
            world
                .borrow()
                .body_poses()
                .into_iter()
                .map(|(p, _)| p)
                .collect()
        },
    )
}

/// Distance between the engines' final positions of each dynamic body: (max, mean), m, and
/// the largest horizontal and vertical parts.
fn position_differences(scene: &Scene, a: &Outcome, b: &Outcome) -> Differences {
    let mut d = Differences::default();
    let mut sum = 0.0;
    let mut n = 0;
    for (_, (p, q)) in scene
        .bodies
        .iter()
        .zip(a.positions.iter().zip(&b.positions))
        .filter(|(spec, _)| spec.is_dynamic())
    {
        let v = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        let dist = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        d.max = d.max.max(dist);
        d.horizontal = d.horizontal.max(v[0].hypot(v[2]));
        d.vertical = d.vertical.max(v[1].abs());
        sum += dist;
        n += 1;
    }
    d.mean = sum / n as f32;
    d
}

/// How far apart two engines' final positions are.
#[derive(Default)]
struct Differences {
    max: f32,
    mean: f32,
    horizontal: f32,
    vertical: f32,
}

/// What the comparison of one scene asserts. Every bound is a measured figure of the default
/// configuration with a margin, which the test that uses it comments.
struct Bounds {
    /// Tumble's largest horizontal drift at any step, m.
    tumble_drift: f32,
    /// Rapier's largest horizontal drift at any step, m: pins the reference, so that "no more
    /// than rapier" cannot loosen past it.
    rapier_drift: f32,
    /// Largest horizontal distance between the engines' final positions of a body, m.
    horizontal_difference: f32,
    /// Largest 3D distance between the engines' final positions of a body, m.
    max_difference: f32,
    /// Mean 3D distance between the engines' final positions over the dynamic bodies, m.
    mean_difference: f32,
    /// Tumble's sag over rapier's as measured, held within [`SAG_RATIO_TOLERANCE`]: tighter
    /// than [`sag_ratio_range`], which is what any structure must satisfy.
    sag_ratio: f32,
}

/// Relative tolerance on a scene's measured sag ratio ([`Bounds::sag_ratio`]): 10%. The ratio
/// is a property of the two engines' contact stiffness and load paths, steady from run to run
/// (both engines are deterministic); dynamic-body contacts 20% softer than configured move the
/// wall's from 0.297 to 0.423 and the pyramid's from 0.319 to 0.451.
const SAG_RATIO_TOLERANCE: f32 = 0.1;

/// Contact stiffness of Tumble's default between two dynamic bodies, and with a fixed body:
/// twice it within the cap of a quarter of the substep rate (`SolverConfig::contact_hertz`),
/// Hz: 60 and 90 at 6 substeps of a 60 Hz step.
fn tumble_hertz() -> (f32, f32) {
    let config = tumble_config();
    let cap = 0.25 * config.solver.substeps as f32 / config.dt;
    let hertz = config.solver.contact_hertz.min(cap);
    (hertz, (2.0 * hertz).min(cap))
}

/// Rapier's contact stiffness between dynamic bodies and with a fixed body, Hz: 30 and 60.
fn rapier_hertz() -> (f32, f32) {
    let p = rapier3d::prelude::IntegrationParameters::default();
    (
        p.contact_softness.natural_frequency,
        p.static_contact_softness.natural_frequency,
    )
}

/// Bounds on Tumble's sag over rapier's: `(lowest, highest)`.
///
/// Both engines' contacts are Box2D-style soft springs that settle `load / (m_eff omega^2)`
/// deep, and both see the same loads and effective masses (same scene), so each contact's sag
/// in Tumble is rapier's times `(f_rapier / f_tumble)^2`: `(30/60)^2 = 0.25` between two
/// dynamic bodies, `(60/90)^2 = 0.44` on the floor. A structure's sag is a sum of contact sags
/// down its load path, so the engines' ratio lies between those two. Measured: column 0.253
/// (26.8 mm against 106.2 mm; the spring model predicts 26.8 and 106.3), wall 0.297, pyramid
/// 0.319. A 4% margin on either side allows for the tilt and friction the spring model leaves
/// out; contacts twice as stiff as they should be (ratio 0.06 on the column) or half as stiff
/// (1.0) fall far outside.
fn sag_ratio_range() -> (f32, f32) {
    let (t, t_static) = tumble_hertz();
    let (r, r_static) = rapier_hertz();
    let a = (r / t).powi(2);
    let b = (r_static / t_static).powi(2);
    (a.min(b) * (1.0 - SAG_MARGIN), a.max(b) * (1.0 + SAG_MARGIN))
}

/// Relative margin on [`sag_ratio_range`].
const SAG_MARGIN: f32 = 0.04;

/// Runs `scene` for its full length in both engines, prints the comparison, and asserts it
/// against `bounds`. Returns both runs for scene-specific checks.
fn compare(scene: &Scene, bounds: &Bounds) -> (Outcome, Outcome) {
    let tumble = run_tumble(scene, scene.steps);
    let rapier = run_rapier(scene, scene.steps);
    let d = position_differences(scene, &tumble, &rapier);
    let (low, high) = sag_ratio_range();
    let ratio = tumble.sag / rapier.sag;
    println!(
        "{}: {} dynamic bodies, {} steps; position difference tumble-rapier: max {:.2} mm, \
         mean {:.2} mm, horizontal {:.2} mm, vertical {:.2} mm; drift: tumble {:.2} mm, \
         rapier {:.2} mm; sag: tumble {:.2} mm, rapier {:.2} mm, ratio {ratio:.3} \
         (expected {low:.3} to {high:.3})",
        scene.name,
        scene.dynamic_count(),
        scene.steps,
        d.max * 1e3,
        d.mean * 1e3,
        d.horizontal * 1e3,
        d.vertical * 1e3,
        tumble.drift * 1e3,
        rapier.drift * 1e3,
        tumble.sag * 1e3,
        rapier.sag * 1e3,
    );
    let mm = |x: f32| x * 1e3;
    let name = &scene.name;
    // A measure, m, at most its bound.
    let within = |what: &str, value: f32, bound: f32| {
        assert!(
            value <= bound,
            "{name}: {what} {:.2} mm, bound {:.2} mm",
            mm(value),
            mm(bound)
        );
    };
    within("tumble drifted", tumble.drift, bounds.tumble_drift);
    within(
        "the reference changed: rapier drifted",
        rapier.drift,
        bounds.rapier_drift,
    );
    assert!(
        tumble.drift <= rapier.drift,
        "{name}: tumble drifted {:.2} mm, more than rapier's {:.2} mm",
        mm(tumble.drift),
        mm(rapier.drift)
    );
    assert!(
        (low..=high).contains(&ratio),
        "{name}: tumble sagged {:.2} mm, rapier {:.2} mm: ratio {ratio:.3}, the contact \
         stiffnesses allow {low:.3} to {high:.3}",
        mm(tumble.sag),
        mm(rapier.sag)
    );
    assert!(
        (ratio - bounds.sag_ratio).abs() <= SAG_RATIO_TOLERANCE * bounds.sag_ratio,
        "{name}: sag ratio {ratio:.3}, measured {:.3} within {SAG_RATIO_TOLERANCE}",
        bounds.sag_ratio
    );
    within(
        "final positions apart sideways by",
        d.horizontal,
        bounds.horizontal_difference,
    );
    assert!(
        d.max <= bounds.max_difference && d.mean <= bounds.mean_difference,
        "{name}: final positions up to {:.2} mm apart (mean {:.2} mm), bounds {:.2} mm \
         (mean {:.2} mm)",
        mm(d.max),
        mm(d.mean),
        mm(bounds.max_difference),
        mm(bounds.mean_difference)
    );
    (tumble, rapier)
}

/// The spring model's sag of the top of a column of `n` unit cubes (1 kg each) under gravity
/// `g`, m, for contacts of `hertz` between cubes and `static_hertz` on the floor: a soft
/// contact settles `load / (m_eff omega^2)` deep; the contact under cube `i` from the top
/// carries `i` cubes with `m_eff = 1/2` kg between two cubes, and the floor's carries all `n`
/// with `m_eff = 1` kg, so the top sinks `g (n (n - 1) / omega^2 + n / omega_static^2)`.
fn column_sag(n: usize, g: f32, hertz: f32, static_hertz: f32) -> f32 {
    let omega = 2.0 * std::f32::consts::PI * hertz;
    let omega_static = 2.0 * std::f32::consts::PI * static_hertz;
    let n = n as f32;
    g * (n * (n - 1.0) / (omega * omega) + n / (omega_static * omega_static))
}

/// Relative error allowed between a column's measured sag and [`column_sag`]: 2%. Measured:
/// Tumble 26.84 mm against 26.84 predicted, rapier 106.24 mm against 106.30. Gravity or a
/// contact stiffness 2% off moves the sag by 2% or 4%.
const COLUMN_SAG_TOLERANCE: f32 = 0.02;

#[test]
fn column_of_20_creeps_no_more_than_in_rapier() {
    let n = 20;
    // Measured: tumble drift 0.00 mm (1e-8 m: the column is symmetric and Tumble keeps it
    // so), rapier 15.9 mm at its worst step (it sways and ends 2.5 mm off). Final positions
    // 79.4 mm apart at most, 52 mm on average, 2.5 mm sideways: the vertical part is the sag
    // difference, 106 mm in rapier against 27 mm in Tumble at the top (the spring model
    // gives 79.5 mm between them).
    let scene = stack(n);
    let (tumble, rapier) = compare(
        &scene,
        &Bounds {
            // A tenth of the scene's 1 cm: a column that starts to lean passes it in seconds.
            tumble_drift: 0.001,
            rapier_drift: 0.025,
            // Twice the 2.5 mm measured.
            horizontal_difference: 0.005,
            // The 79.5 mm of sag difference plus 10 mm; the mean, 52 mm, plus 8 mm.
            max_difference: 0.09,
            mean_difference: 0.06,
            sag_ratio: 0.253,
        },
    );
    // Each engine's sag is its own contacts' spring model: the 79 mm between the engines is
    // the stiffness difference, and Tumble's stiffness is the one its configuration states.
    let g = -scene.gravity[1];
    for (name, outcome, (hertz, static_hertz)) in [
        ("tumble", &tumble, tumble_hertz()),
        ("rapier", &rapier, rapier_hertz()),
    ] {
        let model = column_sag(n, g, hertz, static_hertz);
        println!(
            "{name}: column sag {:.3} mm, spring model {:.3} mm",
            outcome.sag * 1e3,
            model * 1e3
        );
        assert!(
            (outcome.sag - model).abs() <= COLUMN_SAG_TOLERANCE * model,
            "{name}: the column sagged {:.3} mm, the spring model of its {hertz} Hz contacts \
             ({static_hertz} Hz on the floor) {:.3} mm",
            outcome.sag * 1e3,
            model * 1e3
        );
    }
}

#[test]
fn pyramid_of_12_creeps_no_more_than_in_rapier() {
    // Measured: tumble drift 0.95 mm, rapier 2.89 mm; final positions 3.68 mm apart at most
    // (3.08 mm sideways, 2.35 mm vertically), 1.19 mm on average; sag 1.10 mm against 3.45 mm.
    compare(
        &pyramid(12),
        &Bounds {
            // Twice the measured drift, a tenth of the stability suite's 2 cm.
            tumble_drift: 0.002,
            rapier_drift: 0.005,
            horizontal_difference: 0.005,
            max_difference: 0.006,
            mean_difference: 0.002,
            sag_ratio: 0.319,
        },
    );
}

#[test]
fn wall_of_10_by_10_creeps_no_more_than_in_rapier() {
    // Measured: tumble drift 3.00 mm, rapier 6.02 mm; final positions 11.07 mm apart at most
    // (4.11 mm sideways, 10.43 mm vertically: sag 4.4 mm against 14.8 mm), 6.38 mm on average.
    compare(
        &wall(10, 10),
        &Bounds {
            // 5 mm: 1.7 times the measured drift, a quarter of the scene's 2 cm.
            tumble_drift: 0.005,
            rapier_drift: 0.01,
            horizontal_difference: 0.007,
            // The 10.4 mm sag difference plus 4.5 mm; the mean plus 2.6 mm.
            max_difference: 0.015,
            mean_difference: 0.009,
            sag_ratio: 0.297,
        },
    );
}

/// Height above the floor the resting box is dropped from, m: it lands and settles rather than
/// starting in exact contact, so the rest height is the solver's equilibrium, not its input.
const DROP_HEIGHT: f32 = 0.1;
/// Steps the dropped box gets to settle: 2 s, far longer than the 0.14 s fall plus the few
/// steps an over-damped contact takes to stop it.
const SETTLE_STEPS: u32 = 120;
/// Speed below which the box counts as resting, m/s: the column test's 1 cm/s.
const REST_SPEED: f32 = 0.01;
/// Allowed difference between the engines' rest heights, m.
///
/// Neither engine keeps a skin or a dead zone in this setup: Tumble's soft step corrects
/// penetration to zero (its Baumgarte slop applies to the Baumgarte solver only), rapier 0.36
/// does too (its `allowed_linear_error`, 5 mm, is documented as not being a dead zone on the
/// position bias), and the scene builder leaves rapier's contact skin at its default of zero.
/// What remains is the static sag of a soft contact: a spring of natural frequency `f` holding
/// a weight sinks `g / (2 pi f)^2`, 0.07 mm at the 60 Hz rapier gives contacts with fixed
/// bodies, 0.28 mm at 30 Hz. 1 mm is several times that sag, yet five times smaller than the
/// 5 mm slop or skin by which an engine holding one would rest lower (or higher): a difference
/// above it means the engines disagree about where a box touches the floor, not about how
/// stiff the touch is.
const REST_HEIGHT_TOLERANCE: f32 = 0.001;

#[test]
fn box_settles_on_the_floor_at_the_same_height_as_in_rapier() {
    let mut scene = Scene::new("rest", "A unit cube dropped 10 cm onto the floor.");
    scene.bodies.push(floor());
    let touching = 0.5;
    scene
        .bodies
        .push(unit_cube([0.0, touching + DROP_HEIGHT, 0.0]));
    let box_index = 1;

    let (mut tumble, handles) = World::from_scene(&scene, tumble_config()).expect("a valid scene");
    let mut rapier = build_rapier_with(&scene, &rapier_options());
    for _ in 0..SETTLE_STEPS {
        tumble.step().expect("a valid world steps");
        rapier.step();
    }
    let h = handles[box_index];
    let tumble_y = tumble.pose(h).expect("live handle").translation.y;
    let tumble_speed = tumble.linear_velocity(h).expect("live handle").norm();
    let rapier_y = rapier.body_poses()[box_index].0[1];
    let v = rapier.body_velocities()[box_index].0;
    let rapier_speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let static_hertz = rapier3d::prelude::IntegrationParameters::default()
        .static_contact_softness
        .natural_frequency;
    let omega = 2.0 * std::f32::consts::PI * static_hertz;
    println!(
        "rest height after {SETTLE_STEPS} steps: tumble {tumble_y:.6} m ({:.3} mm deep), \
         rapier {rapier_y:.6} m ({:.3} mm deep); spring sag g/omega^2 at {static_hertz} Hz: \
         {:.3} mm",
        (touching - tumble_y) * 1e3,
        (touching - rapier_y) * 1e3,
        9.81 / (omega * omega) * 1e3,
    );
    assert!(
        tumble_speed < REST_SPEED && rapier_speed < REST_SPEED,
        "the box must be at rest before heights compare: tumble {tumble_speed} m/s, \
         rapier {rapier_speed} m/s"
    );
    assert!(
        (tumble_y - rapier_y).abs() <= REST_HEIGHT_TOLERANCE,
        "rest heights differ: tumble {tumble_y} m, rapier {rapier_y} m"
    );
}
