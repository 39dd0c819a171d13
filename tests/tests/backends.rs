//! `Backend::Cpu` against `Backend::Gpu` (the whole step on the GPU) and `Backend::Hybrid`
//! (collision on the GPU, the CPU solver) at the `World` level: the same scene built in each,
//! stepped side by side, every body's position and rotation compared after every step.
//!
//! The scene has two parts that never touch: a 3 x 3 x 3 pile of unit cubes dropped layer on
//! layer (free fall, impacts, stacking), and three lone cubes sliding to a stop on the floor
//! (Coulomb friction, no impacts). The backends are not bitwise equal: the GPU's narrow phase
//! rounds differently and its coloring is parallel rounds under hashed priorities, where the
//! CPU's default colors greedily from the top of a pile down. With one velocity pass per
//! substep the visiting order moves a cube by millimetres during an impact, so the GPU is
//! compared with the CPU solving in the GPU's algorithm (`SolveOrder::ColoredInRounds`), and
//! computing every manifold every step as the GPU does (no contact recycling). The bounds below are measured figures with a
//! margin, for each part and each phase, so that the loose bound of the impacts does not hide
//! an error where the backends agree closely: free flight, sliding and rest.
//!
//! Each backend's final state is also checked for what the scene must end as: a pile of nine
//! upright columns resting where they were dropped, and sliders stopped at Coulomb's distance.
//!
//! Run time on 2 cores with lavapipe: about 10 s for the file, 5 s of CPU time.
//!
//! Needs a GPU (or lavapipe): without one the GPU tests print "skipped: no GPU adapter" and
//! pass, unless `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.

use tumble::prelude::*;
use tumble::scenes::{BodySpec, Scene};
use tumble_gpu::GpuContext;
use tumble_scenes::builders::common::floor;

/// Cubes along each side of the pile.
const PILE_SIDE: usize = 3;
/// Distance between neighbouring columns of the pile, m: 10 cm gaps, so the columns only
/// touch if a cube is knocked sideways.
const PILE_PITCH: Real = 1.1;
/// Height of the bottom layer's faces above the floor at the start, m. Every layer falls onto
/// the one below once that has stopped: the bottom one at 2.4 m/s on the floor, the others at
/// 3.1 and 3.6 m/s.
const PILE_DROP: Real = 0.3;
/// Gap between the pile's layers at the start, m.
const PILE_LAYER_GAP: Real = 0.2;
/// Initial speeds of the sliders along x, m/s.
const SLIDER_SPEEDS: [Real; 3] = [2.0, 3.0, 4.0];
/// z of the sliders' lane, m: 3.9 m clear of the pile.
const SLIDER_Z: Real = 6.0;
/// x spacing of the sliders, m: farther apart than the farthest slide (1.36 m), so they never
/// meet.
const SLIDER_SPACING: Real = 3.0;
/// Steps compared: 2 s. The top layer lands at step 23 and the pile is settled by step 30; the
/// fastest slider stops at step 41; the rest is a second of resting contact, where drift
/// between backends would show.
const STEPS: usize = 120;
/// Steps of free flight compared with [`FREE_FLIGHT_TOLERANCE`]: the bottom layer is still
/// 10 cm above the floor after 0.2 s, out of reach of the speculative margin (2 cm plus the
/// approach speed times `dt`, 5.3 cm then).
const FREE_FLIGHT_STEPS: usize = 12;

/// The scene, and the scene indices of the pile's cubes and of the sliders.
fn pile_and_sliders() -> (Scene, Vec<usize>, Vec<usize>) {
    let mut scene = Scene::new(
        "pile_and_sliders",
        "A 3 x 3 x 3 pile dropped layer on layer, and three cubes sliding to a stop.",
    );
    scene.bodies.push(floor());
    let mut pile = Vec::new();
    let centre = (PILE_SIDE as Real - 1.0) * 0.5;
    for layer in 0..PILE_SIDE {
        let y = 0.5 + PILE_DROP + layer as Real * (1.0 + PILE_LAYER_GAP);
        for i in 0..PILE_SIDE {
            for j in 0..PILE_SIDE {
                let x = (i as Real - centre) * PILE_PITCH;
                let z = (j as Real - centre) * PILE_PITCH;
                pile.push(scene.bodies.len());
                scene.bodies.push(BodySpec::dynamic([0.5; 3], [x, y, z]));
            }
        }
    }
    let mut sliders = Vec::new();
    for (k, &v) in SLIDER_SPEEDS.iter().enumerate() {
        let x = (k as Real - 1.0) * SLIDER_SPACING;
        sliders.push(scene.bodies.len());
        scene.bodies.push(
            BodySpec::dynamic([0.5; 3], [x, 0.5, SLIDER_Z]).with_linear_velocity([v, 0.0, 0.0]),
        );
    }
    (scene, pile, sliders)
}

/// Every body's pose after every step, and the final velocities.
struct Trajectory {
    poses: Vec<Vec<Pose>>,
    final_speeds: Vec<Real>,
}

/// `scene` stepped on `backend`, the solver visiting the constraints in `order`.
fn run(scene: &Scene, backend: Backend, order: SolveOrder) -> Trajectory {
    let mut config = WorldConfig {
        backend,
        // Every manifold computed every step on both sides: near the recycle tolerance the
        // two sides' rounding decides differently which pairs keep theirs, and a recycled
        // point may sit up to its 1 mm tolerance from a fresh one (`tests/tests/recycling.rs`).
        recycle_distance: 0.0,
        ..WorldConfig::default()
    };
    config.solver.order = order;
    let (mut world, handles) = World::from_scene(scene, config).expect("a valid scene");
    let mut poses = Vec::with_capacity(STEPS);
    for _ in 0..STEPS {
        world.step().expect("a valid world steps");
        poses.push(handles.iter().map(|&h| world.pose(h).unwrap()).collect());
    }
    let final_speeds = handles
        .iter()
        .map(|&h| {
            let v = world.linear_velocity(h).unwrap().norm();
            let w = world.angular_velocity(h).unwrap().norm();
            // A point of a unit cube moves at most |v| + |w| sqrt(3) / 2.
            v + w * 0.5 * (3.0 as Real).sqrt()
        })
        .collect();
    Trajectory {
        poses,
        final_speeds,
    }
}

/// Largest position (m) and rotation (rad) difference between two runs over `bodies`, for the
/// steps in `steps`.
fn difference(
    a: &Trajectory,
    b: &Trajectory,
    bodies: &[usize],
    steps: std::ops::Range<usize>,
) -> (Real, Real) {
    let mut worst = (0.0 as Real, 0.0 as Real);
    for step in steps {
        for &i in bodies {
            let (p, q) = (&a.poses[step][i], &b.poses[step][i]);
            let d = (p.translation.vector - q.translation.vector).norm();
            let r = p.rotation.angle_to(&q.rotation);
            worst = (worst.0.max(d), worst.1.max(r));
        }
    }
    worst
}

/// How far another backend may be from the CPU: (position m, rotation rad) per part and phase.
struct Tolerances {
    /// The pile at every step, impacts included.
    pile: (Real, Real),
    /// The sliders at every step.
    sliders: (Real, Real),
    /// Every body at the last step, at rest.
    rest: (Real, Real),
}

/// Free flight is the same arithmetic on every backend (gravity, then the position update),
/// measured bit-identical on lavapipe: 1 um allows a few f32 roundings at these heights (the
/// spacing is 0.06 to 0.24 um from 0.5 to 4 m) and is 200 times smaller than the 0.2 mm by which a
/// gravity 0.1% off moves a cube in those 12 steps.
const FREE_FLIGHT_TOLERANCE: Real = 1e-6;

/// Runs the scene on the CPU with the solver order `cpu_order` and on `backend`, prints the
/// differences, and asserts them against `tolerances`; then asserts `backend`'s own final
/// state.
fn compare_with_cpu(backend: Backend, cpu_order: SolveOrder, tolerances: &Tolerances) {
    let (scene, pile, sliders) = pile_and_sliders();
    let cpu = run(&scene, Backend::Cpu, cpu_order);
    let other = run(&scene, backend, SolverConfig::default().order);
    let all: Vec<usize> = (1..scene.bodies.len()).collect();

    let free = difference(&cpu, &other, &pile, 0..FREE_FLIGHT_STEPS);
    let pile_diff = difference(&cpu, &other, &pile, 0..STEPS);
    let slider_diff = difference(&cpu, &other, &sliders, 0..STEPS);
    let rest = difference(&cpu, &other, &all, STEPS - 1..STEPS);
    println!(
        "{backend:?} against Cpu ({cpu_order:?}): free flight {:.2e} m; pile {:.2e} m, {:.2e} rad; sliders \
         {:.2e} m, {:.2e} rad; at rest {:.2e} m, {:.2e} rad",
        free.0, pile_diff.0, pile_diff.1, slider_diff.0, slider_diff.1, rest.0, rest.1
    );
    assert!(
        free.0 <= FREE_FLIGHT_TOLERANCE,
        "{backend:?}: free flight {} m from the CPU's",
        free.0
    );
    for (what, measured, bound) in [
        ("pile", pile_diff, tolerances.pile),
        ("sliders", slider_diff, tolerances.sliders),
        ("rest", rest, tolerances.rest),
    ] {
        assert!(
            measured.0 <= bound.0 && measured.1 <= bound.1,
            "{backend:?} {what}: {} m and {} rad from the CPU's, bounds {} m and {} rad",
            measured.0,
            measured.1,
            bound.0,
            bound.1
        );
    }
    final_state_is_plausible(&scene, &pile, &sliders, &other, backend);
}

/// Speed below which a body counts as resting, m/s (the stability suite's 1 cm/s).
const REST_SPEED: Real = 0.01;
/// How far a pile cube may end from straight below its start, m: it is dropped straight onto
/// an aligned cube, so any sideways motion is the solver's; a cube that slid off or a column
/// that leaned would be centimetres off.
const PILE_SIDEWAYS: Real = 0.005;
/// How far a pile cube's centre may end from its layer's touching height, m: the top layer
/// ends 0.5 mm low, the sum of the soft contacts' sag below it at the default stiffness; 2 mm
/// is four times that, far less than a cube pushed into the one below or resting on a tilt.
const PILE_SAG: Real = 0.002;
/// Tilt allowed for a pile cube at rest, rad (0.5 degree): it lands flat on a flat face.
const PILE_TILT: Real = 0.5 * std::f32::consts::PI / 180.0;
/// Relative error allowed on a slider's stopping distance against Coulomb's `v^2 / (2 mu g)`:
/// 3%. A soft contact lets a body slide a little past the rigid answer (measured 0.8% to 1%
/// over it); a friction coefficient 5% off changes the distance by 5%.
const SLIDE_TOLERANCE: Real = 0.03;

/// `backend`'s final state: every cube at rest, the pile standing as nine upright columns
/// where it was dropped, each slider stopped at Coulomb's distance.
fn final_state_is_plausible(
    scene: &Scene,
    pile: &[usize],
    sliders: &[usize],
    run: &Trajectory,
    backend: Backend,
) {
    let last = run.poses.last().expect("steps were taken");
    for i in 1..scene.bodies.len() {
        assert!(
            run.final_speeds[i] < REST_SPEED,
            "{backend:?}: body {i} still moves at {} m/s",
            run.final_speeds[i]
        );
    }
    let g = -scene.gravity[1];
    let mut worst = (0.0 as Real, 0.0 as Real, 0.0 as Real);
    for (k, &i) in pile.iter().enumerate() {
        let start = scene.bodies[i].position;
        let p = last[i].translation.vector;
        let layer = (k / (PILE_SIDE * PILE_SIDE)) as Real;
        let touching = 0.5 + layer;
        let sideways = (p.x - start[0]).hypot(p.z - start[2]);
        let sag = touching - p.y;
        let tilt = last[i].rotation.angle();
        assert!(
            sideways < PILE_SIDEWAYS && (-PILE_SAG..PILE_SAG).contains(&sag) && tilt < PILE_TILT,
            "{backend:?}: pile cube {k} ended {sideways} m sideways, {sag} m below its rest \
             height, tilted {tilt} rad"
        );
        worst = (
            worst.0.max(sideways),
            worst.1.max(sag.abs()),
            worst.2.max(tilt),
        );
    }
    println!(
        "{backend:?}: pile at rest: {:.2e} m sideways, {:.2e} m from rest height, {:.2e} rad \
         tilt at most",
        worst.0, worst.1, worst.2
    );
    for (&i, &v) in sliders.iter().zip(&SLIDER_SPEEDS) {
        let mu = (scene.bodies[i].friction * scene.bodies[0].friction).sqrt();
        let coulomb = v * v / (2.0 * mu * g);
        let slid = last[i].translation.x - scene.bodies[i].position[0];
        println!("{backend:?}: slider at {v} m/s slid {slid:.4} m, Coulomb {coulomb:.4} m");
        assert!(
            (slid - coulomb).abs() <= SLIDE_TOLERANCE * coulomb,
            "{backend:?}: the slider at {v} m/s slid {slid} m, Coulomb says {coulomb} m"
        );
    }
}

/// The CPU's final state in both colored orders: the top-down greedy coloring (the default)
/// and the GPU's hashed rounds. The order moves the impacts by millimetres (below), not where
/// the pile comes to rest.
#[test]
fn cpu_pile_stands_and_sliders_stop_at_coulombs_distance() {
    let (scene, pile, sliders) = pile_and_sliders();
    for order in [SolveOrder::Colored, SolveOrder::ColoredInRounds] {
        let cpu = run(&scene, Backend::Cpu, order);
        final_state_is_plausible(&scene, &pile, &sliders, &cpu, Backend::Cpu);
    }
}

/// `Backend::Gpu` against the CPU solving in the GPU's coloring algorithm
/// (`SolveOrder::ColoredInRounds`). With one velocity pass per substep the order in which
/// constraints are visited moves an impact's trajectory: on lavapipe the CPU in its default
/// top-down order and the CPU in hashed rounds end the pile 5.7 mm and 4.9e-3 rad apart during
/// the impacts and 2.4 mm apart at rest, and the GPU against the default CPU measured exactly
/// that. Against the CPU in rounds (which differs from the GPU only in the seeding by last
/// step's colors, the manifolds' indices and the rounding of the narrow phase) it measured:
/// pile 1.28 mm and 6.3e-4 rad, sliders 0.13 mm and 4.3e-4 rad, at rest 0.62 mm and 4.3e-4
/// rad.
///
/// Bounds about five times those (at rest about three times, below the 2.4 mm that the other
/// order gives, so a GPU that colored some other way shows). A friction coefficient 1% off
/// moves the fastest slider's stop by 14 mm, 28 times the sliders' 0.5 mm; a dropped substep
/// shows in free flight.
#[test]
fn gpu_follows_the_cpu_trajectory() {
    if GpuContext::for_tests().is_none() {
        return;
    }
    compare_with_cpu(
        Backend::Gpu,
        SolveOrder::ColoredInRounds,
        &Tolerances {
            pile: (6e-3, 3e-3),
            sliders: (5e-4, 2e-3),
            rest: (2e-3, 2e-3),
        },
    );
}

/// `Backend::Hybrid` against the CPU: the same solver in the same order on manifolds the GPU
/// computed, which round differently in the last bits. Measured on lavapipe: pile 0.029 mm
/// and 2.2e-5 rad, sliders 0.033 mm and 2.1e-4 rad, at rest 0.028 mm and 1.8e-4 rad. Bounds
/// about ten times those in position and rotation: 0.3 mm and 2e-4 rad for the pile, 0.3 mm
/// and 2e-3 rad elsewhere. Ten times tighter than the GPU's on the pile, as no solver order
/// differs: a manifold whose depth or normal the GPU got wrong shows there.
#[test]
fn hybrid_follows_the_cpu_trajectory() {
    if GpuContext::for_tests().is_none() {
        return;
    }
    compare_with_cpu(
        Backend::Hybrid,
        SolveOrder::Colored,
        &Tolerances {
            pile: (3e-4, 2e-4),
            sliders: (3e-4, 2e-3),
            rest: (3e-4, 2e-3),
        },
    );
}
