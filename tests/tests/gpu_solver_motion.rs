//! The GPU world's motion against the CPU integrators and the physics it must reproduce:
//! free fall, a spinning box's angular momentum, and columns and pyramids that stand (split
//! from `gpu_solver.rs`, which checks the coloring, preparation and solve stages). These tests
//! print a loud "skipped" without an adapter unless `TUMBLE_REQUIRE_GPU=1`, which makes it a
//! failure.

use tumble_geometry::{Real, Vec3};
use tumble_gpu::GpuContext;
use tumble_gpu::step::{GpuWorld, GpuWorldConfig, ReadRequest};
use tumble_solver::{Body, BodyKind, BodyState, Coloring, SolverConfig, finalize_bodies};
use tumble_tests::gpu_solver_util::{DT, assert_close, cube, gravity};

/// The solver settings of every world here, GPU and CPU twin alike: the default (6 substeps
/// at 60 Hz). Both sides take it from this one function, so a twin cannot silently run other
/// settings than the world it checks.
fn solver_config() -> SolverConfig {
    SolverConfig::default()
}

/// A world stepping entirely on the GPU (collision and solver) with `gravity` and
/// [`solver_config`].
fn gpu_world(ctx: &GpuContext, gravity: Vec3, bodies: &[Body], states: &[BodyState]) -> GpuWorld {
    let config = GpuWorldConfig {
        gravity,
        dt: DT,
        solver: solver_config(),
        ..Default::default()
    };
    let mut world = GpuWorld::new(ctx, config).unwrap();
    world.set_bodies(bodies, states).unwrap();
    world
}

/// One step of the CPU twin: tumble-solver's solve stage with [`solver_config`] (no
/// contacts), then the pose update, as the GPU step runs them.
fn cpu_step(bodies: &mut [Body], states: &mut [BodyState], gravity: &Vec3) {
    let empty = Coloring::from_colors(Vec::new());
    let config = solver_config();
    tumble_solver::solve(bodies, states, &mut [], &empty, &config, DT, gravity);
    finalize_bodies(bodies, states);
}

#[test]
fn free_fall_for_one_second_matches_semi_implicit_euler() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let body = cube(BodyKind::Dynamic, Vec3::new(0.0, 10.0, 0.0));
    let v0 = Vec3::new(1.0, 2.0, 0.0);
    let mut world = gpu_world(
        &ctx,
        gravity(),
        &[body],
        &[BodyState::moving(v0, Vec3::zeros())],
    );
    let steps = 60;
    for _ in 0..steps {
        world.step().unwrap();
    }
    let snap = world.read_now(ReadRequest::MOTION).unwrap();
    // Semi-implicit Euler with the world's substeps: v_k = v0 + k g h,
    // x_n = x0 + n h v0 + g h^2 n (n+1)/2.
    let substeps = solver_config().substeps;
    let n = f64::from(steps * substeps);
    let h = f64::from(DT) / f64::from(substeps);
    let y = 10.0 + n * h * 2.0 - 9.81 * h * h * n * (n + 1.0) / 2.0;
    let p = snap.pose(0).translation.vector;
    // n (360 at 6 substeps) f32 additions of values up to 10 m round to ~n ulp(10) = 3.4e-4 m
    // at worst. Explicit Euler is off by g h^2 n = 2.7 cm, and one substep more or fewer per
    // step by (g/2) (1 s)^2 |1/n - 1/n'| = 1.9 to 2.7 mm.
    let tolerance = n * f64::from(f32::EPSILON) * 8.0;
    assert!((f64::from(p.y) - y).abs() < tolerance, "y {} vs {y}", p.y);
    assert!(
        (f64::from(p.x) - n * h).abs() < tolerance,
        "x {} vs {}",
        p.x,
        n * h
    );
    let v = snap.state(0).linear_velocity;
    assert!(
        (f64::from(v.y) - (2.0 - 9.81 * n * h)).abs() < 1e-4,
        "vy {}",
        v.y
    );
}

#[test]
fn spinning_box_keeps_its_angular_momentum_and_follows_the_cpu() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // The canonical 1 x 2 x 3 box spinning about its major axis with a wobble, zero gravity.
    let (bodies, states) = bodies_of(&tumble_scenes::spinning_box());
    let (body, state) = (bodies[0], states[0]);
    let mut world = gpu_world(&ctx, Vec3::zeros(), &bodies, &states);
    let (mut cpu_bodies, mut cpu_states) = (bodies.clone(), states.clone());
    // World angular momentum and kinetic energy.
    let momentum = |b: &Body, s: &BodyState| -> (Vec3, Real) {
        let local = b
            .pose
            .rotation
            .inverse_transform_vector(&s.angular_velocity);
        let l = b.inertia_local().component_mul(&local);
        (b.pose.rotation * l, 0.5 * local.dot(&l))
    };
    let (l0, e0) = momentum(&body, &state);
    for second in 1..=10 {
        for _ in 0..60 {
            world.step().unwrap();
            cpu_step(&mut cpu_bodies, &mut cpu_states, &Vec3::zeros());
        }
        let snap = world.read_now(ReadRequest::MOTION).unwrap();
        let mut gpu_body = body;
        gpu_body.pose = snap.pose(0);
        let (l, e) = momentum(&gpu_body, &snap.state(0));
        // The stability suite's bounds: the momentum vector within 1%, no energy growth past
        // 1e-4 (the split implicit-midpoint update conserves both up to round-off).
        assert!(
            (l - l0).norm() < MOMENTUM_TOLERANCE * l0.norm(),
            "{second} s: L {l0} -> {l}"
        );
        assert!(
            e <= e0 * (1.0 + ENERGY_GROWTH),
            "{second} s: energy grew {e0} -> {e}"
        );
        // The GPU follows its CPU twin. Both integrate the same equations with the same
        // substeps in f32, in different operation orders (GPU quaternion code against
        // nalgebra's), so their spin rates differ by a few ulp of |w| ~ 6.2 rad/s
        // (eps |w| = 7e-7 rad/s) and their attitudes part at about that rate: measured on
        // lavapipe, at most 2.9e-6 rad per second of run. The bound, 1e-5 rad per second,
        // leaves 3.4x. A substep more or fewer on one side changes the integrator's O(h^2)
        // phase error instead, and the attitudes part at 4.9e-5 (7 substeps against 6) to
        // 7.4e-5 rad per second (5 against 6): 5x past the bound, from the first check.
        let t = second as Real;
        let (gpu_pose, cpu_pose) = (snap.pose(0), cpu_bodies[0].pose);
        let apart = gpu_pose.rotation.angle_to(&cpu_pose.rotation);
        let (gw, cw) = (
            snap.state(0).angular_velocity,
            cpu_states[0].angular_velocity,
        );
        assert!(
            apart < ATTITUDE_SPLIT_PER_SECOND * t,
            "{second} s: attitude {apart} rad from the CPU twin's"
        );
        // The world spin vector precesses with the wobble, so the attitude's tiny phase
        // offset shows in it amplified: measured up to 7.7e-5 rad/s in 10 s. 2e-4 rad/s
        // (3e-5 of |w|) leaves 2.5x; it is the attitude that resolves a substep.
        assert_close("spin", gw.as_slice(), cw.as_slice(), 2e-4, 0.0, 0.0);
    }
}

/// How fast the GPU's and the CPU twin's attitudes may part, rad/s (derivation in the test).
const ATTITUDE_SPLIT_PER_SECOND: Real = 1e-5;

// ---------------------------------------------------------------------------------------------
// Scenes that must stand, entirely on the GPU
// ---------------------------------------------------------------------------------------------

use tumble_scenes::Scene;
use tumble_tests::scene_support::bodies_of;
use tumble_tests::stability::{
    COLUMN_DRIFT, ENERGY_GROWTH, MOMENTUM_TOLERANCE, PYRAMID_DRIFT, REST_SPEED, TEN_SECONDS,
};

/// Steps between drift checks: drift is a slow creep (a column that buckles takes seconds),
/// so a check every sixth of a second sees it, at a tenth of the readbacks.
const CHECK_EVERY: usize = 10;

/// Runs `scene` for `steps` steps entirely on the GPU: the horizontal drift of every dynamic
/// body stays under `max_drift` at every check, and at the end every point of every body is
/// slower than `max_end_speed` (the CPU stability suite's checks and thresholds).
fn stands_on_gpu(
    ctx: &GpuContext,
    scene: &Scene,
    steps: usize,
    max_drift: Real,
    max_end_speed: Option<Real>,
) {
    let (bodies, states) = bodies_of(scene);
    let mut world = gpu_world(ctx, Vec3::from(scene.gravity), &bodies, &states);
    let dynamic: Vec<usize> = (0..bodies.len())
        .filter(|&i| bodies[i].is_dynamic())
        .collect();
    let mut worst: Real = 0.0;
    let mut snap = world.read_now(ReadRequest::MOTION).unwrap();
    for step in 1..=steps {
        world.step().unwrap();
        if step % CHECK_EVERY != 0 && step != steps {
            continue;
        }
        snap = world.read_now(ReadRequest::MOTION).unwrap();
        for &i in &dynamic {
            let d = snap.pose(i).translation.vector - bodies[i].pose.translation.vector;
            let p = snap.pose(i).translation.vector;
            assert!(
                p.iter().all(|c| c.is_finite()),
                "{}: body {i} not finite",
                scene.name
            );
            worst = worst.max((d.x * d.x + d.z * d.z).sqrt());
        }
        assert!(
            worst < max_drift,
            "{}: drifted {worst} m sideways by step {step}, limit {max_drift} m",
            scene.name
        );
    }
    if let Some(limit) = max_end_speed {
        let speed = dynamic
            .iter()
            .map(|&i| {
                let s = snap.state(i);
                s.linear_velocity.norm()
                    + s.angular_velocity.norm() * bodies[i].shape.half_extents.norm()
            })
            .fold(0.0, Real::max);
        assert!(
            speed < limit,
            "{}: still moving at {speed} m/s after {steps} steps",
            scene.name
        );
    }
}

#[test]
fn a_column_of_20_cubes_stands_10_s_on_the_gpu() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    stands_on_gpu(
        &ctx,
        &tumble_scenes::stack(20),
        TEN_SECONDS,
        COLUMN_DRIFT,
        Some(REST_SPEED),
    );
}

#[test]
fn a_pyramid_of_5_layers_stands_10_s_on_the_gpu() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    stands_on_gpu(
        &ctx,
        &tumble_scenes::pyramid(5),
        TEN_SECONDS,
        PYRAMID_DRIFT,
        None,
    );
}
