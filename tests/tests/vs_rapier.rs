//! Tumble against rapier3d on the same canonical scenes.
//!
//! Both engines build each scene from the same `tumble-scenes` data (sizes, masses, materials,
//! time step) and run it for the scene's 10 s (600 steps at 60 Hz) at matched substeps:
//! Tumble's default soft step with 4 substeps against rapier's 4 solver iterations, which in
//! rapier's soft-step solver are substeps too. Each test prints how far the engines end up
//! apart body by body and how far each let the structure creep sideways, and asserts that
//! Tumble creeps no more than rapier does, give or take a few millimetres. A last test drops a
//! box on the floor and compares the heights at which the two engines let it rest.
//!
//! Run time on 2 cores: 11 s for the file, up to 27 s while other builds share the cores
//! (`cargo test -p tumble-tests --test vs_rapier -- --nocapture` prints the figures). The
//! 650-cube pyramid is nearly all of it, most of that Tumble's 600 steps; the column, the wall
//! and the dropped box take about 1 s together.

use tumble::prelude::*;
use tumble_scenes::builders::common::{floor, unit_cube};
use tumble_scenes::{RapierOptions, Scene, build_rapier_with, pyramid, stack, wall};

/// Tolerance on the drift comparison, m. Both solvers are soft and converge differently within
/// a step, so their creep is not equal to the micrometre; 5 mm is half the 1 cm a column may
/// creep in the stability suite, so a Tumble that creeps visibly more than rapier fails while
/// solver noise does not.
const DRIFT_MARGIN: f32 = 0.005;

/// Final state of one engine on one scene.
struct Outcome {
    /// Final centre of every body, in scene order.
    positions: Vec<[f32; 3]>,
    /// Largest horizontal displacement of any dynamic body from its start, m.
    drift: f32,
}

/// The largest horizontal (x-z) displacement of any dynamic body from its scene position.
fn horizontal_drift(scene: &Scene, positions: &[[f32; 3]]) -> f32 {
    scene
        .bodies
        .iter()
        .zip(positions)
        .filter(|(spec, _)| spec.is_dynamic())
        .map(|(spec, p)| {
            let dx = p[0] - spec.position[0];
            let dz = p[2] - spec.position[2];
            (dx * dx + dz * dz).sqrt()
        })
        .fold(0.0, f32::max)
}

/// Tumble's default configuration: soft step, 4 substeps, CPU.
fn tumble_config() -> WorldConfig {
    WorldConfig::default()
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

fn run_tumble(scene: &Scene, steps: u32) -> Outcome {
    let (mut world, handles) =
        World::from_scene(scene, tumble_config()).expect("canonical scenes are valid");
    for _ in 0..steps {
        world.step().expect("a valid world steps");
    }
    let positions: Vec<[f32; 3]> = handles
        .iter()
        .map(|&h| {
            let t = world.pose(h).expect("live handle").translation.vector;
            [t.x, t.y, t.z]
        })
        .collect();
    Outcome {
        drift: horizontal_drift(scene, &positions),
        positions,
    }
}

fn run_rapier(scene: &Scene, steps: u32) -> Outcome {
    let mut world = build_rapier_with(scene, &rapier_options());
    for _ in 0..steps {
        world.step();
    }
    let positions: Vec<[f32; 3]> = world.body_poses().into_iter().map(|(p, _)| p).collect();
    Outcome {
        drift: horizontal_drift(scene, &positions),
        positions,
    }
}

/// Distance between the engines' final positions of each dynamic body: (max, mean), m.
fn position_differences(scene: &Scene, a: &Outcome, b: &Outcome) -> (f32, f32) {
    let distances: Vec<f32> = scene
        .bodies
        .iter()
        .zip(a.positions.iter().zip(&b.positions))
        .filter(|(spec, _)| spec.is_dynamic())
        .map(|(_, (p, q))| {
            let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
        })
        .collect();
    let max = distances.iter().copied().fold(0.0, f32::max);
    let mean = distances.iter().sum::<f32>() / distances.len() as f32;
    (max, mean)
}

/// Runs `scene` for its full length in both engines, prints the comparison, and asserts that
/// Tumble's drift is at most rapier's plus [`DRIFT_MARGIN`].
fn compare_drift(scene: &Scene) {
    let tumble = run_tumble(scene, scene.steps);
    let rapier = run_rapier(scene, scene.steps);
    let (max_diff, mean_diff) = position_differences(scene, &tumble, &rapier);
    println!(
        "{}: {} dynamic bodies, {} steps; position difference tumble-rapier: max {:.2} mm, \
         mean {:.2} mm; drift: tumble {:.2} mm, rapier {:.2} mm",
        scene.name,
        scene.dynamic_count(),
        scene.steps,
        max_diff * 1e3,
        mean_diff * 1e3,
        tumble.drift * 1e3,
        rapier.drift * 1e3,
    );
    for (name, outcome) in [("tumble", &tumble), ("rapier", &rapier)] {
        assert!(
            outcome.positions.iter().flatten().all(|x| x.is_finite()),
            "{}: {name} produced a non-finite position",
            scene.name
        );
    }
    assert!(
        tumble.drift <= rapier.drift + DRIFT_MARGIN,
        "{}: tumble drifted {:.2} mm, rapier {:.2} mm (allowed: rapier + {:.0} mm)",
        scene.name,
        tumble.drift * 1e3,
        rapier.drift * 1e3,
        DRIFT_MARGIN * 1e3
    );
}

#[test]
fn column_of_20_creeps_no_more_than_in_rapier() {
    compare_drift(&stack(20));
}

#[test]
fn pyramid_of_12_creeps_no_more_than_in_rapier() {
    compare_drift(&pyramid(12));
}

#[test]
fn wall_of_10_by_10_creeps_no_more_than_in_rapier() {
    compare_drift(&wall(10, 10));
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
