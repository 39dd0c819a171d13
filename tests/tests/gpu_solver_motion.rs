//! The GPU world's motion against the CPU integrators and the physics it must reproduce:
//! free fall, a spinning box's angular momentum, and columns and pyramids that stand (split
//! from `gpu_solver.rs`, which checks the coloring, preparation and solve stages). These tests
//! print a loud "skipped" without an adapter unless `TUMBLE_REQUIRE_GPU=1`, which makes it a
//! failure.

use tumble_geometry::{Cuboid, Pose, Real, Vec3};
use tumble_gpu::GpuContext;
use tumble_gpu::step::{GpuWorld, GpuWorldConfig, ReadRequest};
use tumble_solver::{Body, BodyKind, BodyState, Material, finalize_bodies};
use tumble_tests::gpu_solver_util::{DT, assert_close, cube, gravity};

use tumble_solver::{begin_step, integrate_positions, integrate_velocities};

/// A world stepping entirely on the GPU (collision and solver) with `gravity`.
fn gpu_world(ctx: &GpuContext, gravity: Vec3, bodies: &[Body], states: &[BodyState]) -> GpuWorld {
    let mut world = GpuWorld::new(
        ctx,
        GpuWorldConfig {
            gravity,
            ..Default::default()
        },
    )
    .unwrap();
    world.set_bodies(bodies, states).unwrap();
    world
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
    // Semi-implicit Euler with the default's substeps: v_k = v0 + k g h,
    // x_n = x0 + n h v0 + g h^2 n (n+1)/2.
    let substeps = tumble_solver::SolverConfig::default().substeps;
    let n = f64::from(steps * substeps);
    let h = f64::from(DT) / f64::from(substeps);
    let y = 10.0 + n * h * 2.0 - 9.81 * h * h * n * (n + 1.0) / 2.0;
    let p = snap.pose(0).translation.vector;
    // n (360 at 6 substeps) f32 additions of values up to 10 m round to ~n ulp(10) = 3.4e-4 m
    // at worst; an explicit-Euler or missing-substep scheme is off by 2.7 cm or more.
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
    let h = DT / 4.0;
    for second in 1..=10 {
        for _ in 0..60 {
            world.step().unwrap();
            begin_step(&mut cpu_states);
            for _ in 0..4 {
                integrate_velocities(&cpu_bodies, &mut cpu_states, &Vec3::zeros(), h);
                integrate_positions(&cpu_bodies, &mut cpu_states, h);
            }
            finalize_bodies(&mut cpu_bodies, &mut cpu_states);
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
        if second == 1 {
            // After 1 s the GPU follows the CPU integrator: both solve the same implicit
            // equations by the same Newton steps; 1e-3 rad/s on ~6 rad/s covers f32
            // differences compounding over 240 substeps.
            let (gw, cw) = (
                snap.state(0).angular_velocity,
                cpu_states[0].angular_velocity,
            );
            assert_close(
                "spin after 1 s",
                gw.as_slice(),
                cw.as_slice(),
                1e-3,
                0.0,
                0.0,
            );
            let (gq, cq) = (
                snap.pose(0).rotation.coords,
                cpu_bodies[0].pose.rotation.coords,
            );
            assert_close(
                "attitude after 1 s",
                gq.as_slice(),
                cq.as_slice(),
                1e-3,
                0.0,
                0.0,
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Scenes that must stand, entirely on the GPU
// ---------------------------------------------------------------------------------------------

use tumble_scenes::{BodyKind as SceneKind, Scene};
use tumble_tests::stability::{
    COLUMN_DRIFT, ENERGY_GROWTH, MOMENTUM_TOLERANCE, PYRAMID_DRIFT, REST_SPEED, TEN_SECONDS,
};

/// The solver's bodies and states of a scene.
fn bodies_of(scene: &Scene) -> (Vec<Body>, Vec<BodyState>) {
    scene
        .bodies
        .iter()
        .map(|s| {
            let kind = match s.kind {
                SceneKind::Fixed => BodyKind::Fixed,
                SceneKind::Dynamic => BodyKind::Dynamic,
                SceneKind::Kinematic => BodyKind::Kinematic,
            };
            let [x, y, z, w] = s.rotation;
            let rotation = tumble_geometry::nalgebra::UnitQuaternion::from_quaternion(
                tumble_geometry::nalgebra::Quaternion::new(w, x, y, z),
            );
            let pose = Pose::from_parts(Vec3::from(s.position).into(), rotation);
            let material = Material {
                friction: s.friction,
                restitution: s.restitution,
            };
            let body = Body::new(
                kind,
                Cuboid::new(Vec3::from(s.half_extents)),
                pose,
                s.density,
                material,
            )
            .unwrap();
            (
                body,
                BodyState::moving(
                    Vec3::from(s.linear_velocity),
                    Vec3::from(s.angular_velocity),
                ),
            )
        })
        .unzip()
}

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
