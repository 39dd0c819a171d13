//! Per-body properties on every backend: collision groups, persistent forces and torques,
//! gravity scales and user data. Each physical effect is compared with its closed form under
//! the integrator's own scheme (semi-implicit Euler over the substeps), and the GPU and
//! Hybrid backends with the CPU; bad values are refused by name, leaving the world as it was.
//!
//! The GPU backends need an adapter (or lavapipe): without one their cases are left out with
//! a "skipped" line, unless `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.

use tumble::prelude::*;
use tumble::{CollisionGroups, Error};
use tumble_gpu::GpuContext;
use tumble_tests::bad_input::{expect_field, snapshot};
use tumble_tests::facade::floor_desc;

/// Steps simulated by the motion tests: 1 s at the default 60 Hz.
const STEPS: usize = 60;

/// The backends to test here: the CPU, and the two GPU ones when an adapter is available.
fn backends() -> Vec<Backend> {
    let mut all = vec![Backend::Cpu];
    if GpuContext::for_tests().is_some() {
        all.extend([Backend::Gpu, Backend::Hybrid]);
    }
    all
}

/// A world with every body awake: these tests follow bodies at rest through their contacts
/// and velocities, which a sleeping island would freeze (and `Backend::Gpu` reports no
/// manifold of a sleeping pair in `World::contacts`).
fn world(backend: Backend, gravity: Vec3) -> World {
    World::new(WorldConfig {
        backend,
        gravity,
        effects: tumble::EffectOverrides::NO_SLEEP,
        ..Default::default()
    })
    .unwrap()
}

/// The substep length `h` and the substeps `n` in `steps` steps of `world`.
fn substeps(world: &World, steps: usize) -> (f64, f64) {
    let c = world.config();
    let per_step = f64::from(c.solver.substeps);
    (f64::from(c.dt) / per_step, per_step * steps as f64)
}

/// Semi-implicit Euler's displacement after `n` substeps of `h` under a constant
/// acceleration `a` from rest: `v_k = k a h`, `x_n = a h^2 n (n + 1) / 2`, which exceeds the
/// exact `a t^2 / 2` by the factor `1 + 1/n`.
fn euler_displacement(a: f64, h: f64, n: f64) -> f64 {
    a * h * h * n * (n + 1.0) / 2.0
}

fn position(world: &World, h: BodyHandle) -> Vec3 {
    world.pose(h).unwrap().translation.vector
}

/// The floor's and the bodies' groups: the floor is in group 1; "debris" is in group 2 and
/// collides with everything but group 1.
const FLOOR_GROUP: u32 = 1;
const DEBRIS: CollisionGroups = CollisionGroups::new(2, !FLOOR_GROUP);

fn touching(world: &World, a: BodyHandle, b: BodyHandle) -> bool {
    world
        .contacts()
        .iter()
        .any(|c| (c.body_a, c.body_b) == (a, b) || (c.body_a, c.body_b) == (b, a))
}

/// A cube whose groups exclude the floor's falls through it; a cube with the default groups,
/// beside it, rests on it. Neither the CPU grid nor the GPU sweep may form the refused pair:
/// no manifold between the floor and the falling cube is ever reported (a manifold exists
/// only for a broad-phase pair, and the cube starts touching the floor, inside the margin).
/// Then `set_collision_groups` gives the resting cube the same groups, and it falls too.
#[test]
fn filtered_cubes_fall_through_the_floor_and_matching_ones_rest_on_it() {
    for backend in backends() {
        let mut world = world(backend, Vec3::new(0.0, -9.81, 0.0));
        let floor = world
            .add_body(floor_desc(5.0).collision_groups(CollisionGroups::new(FLOOR_GROUP, u32::MAX)))
            .unwrap();
        let ghost = world
            .add_body(
                BodyDesc::dynamic()
                    .translation(-2.0, 0.5, 0.0)
                    .collision_groups(DEBRIS),
            )
            .unwrap();
        let resting = world
            .add_body(BodyDesc::dynamic().translation(2.0, 0.5, 0.0))
            .unwrap();
        assert_eq!(world.collision_groups(ghost).unwrap(), DEBRIS);
        assert_eq!(
            world.collision_groups(resting).unwrap(),
            CollisionGroups::ALL
        );
        for step in 0..STEPS {
            world.step().unwrap();
            assert!(
                !touching(&world, floor, ghost),
                "{backend:?}: step {step} paired the floor with a cube whose groups refuse it"
            );
        }
        assert!(
            touching(&world, floor, resting),
            "{backend:?}: the resting cube has no contact"
        );
        let (h, n) = substeps(&world, STEPS);
        let fallen = 0.5 - euler_displacement(9.81, h, n);
        let y = f64::from(position(&world, ghost).y);
        // Free fall, as if there were no floor: 4.9 m in 1 s, far below the floor's bottom
        // face (y = -1). 1 mm allows the f32 rounding of 360 position updates (about 1e-6 m
        // each at these heights) and is 20 times smaller than the 2 cm a floor contact held
        // for a single step would cost.
        assert!(
            (y - fallen).abs() < 1e-3,
            "{backend:?}: ghost y {y}, free fall {fallen}"
        );
        // At rest on the floor: the solver tolerates an overlap of at most the 5 mm slop.
        let y = position(&world, resting).y;
        assert!((y - 0.5).abs() < 5e-3, "{backend:?}: resting cube y {y}");

        world.set_collision_groups(resting, DEBRIS).unwrap();
        for _ in 0..STEPS {
            world.step().unwrap();
        }
        // Below the floor's bottom face after 1 s: the change reached the broad phase (a
        // cube still held by the floor would be at 0.5).
        let y = position(&world, resting).y;
        assert!(y < -3.0, "{backend:?}: re-grouped cube y {y}");
        assert!(!touching(&world, floor, resting));
    }
}

/// The CPU pair list itself (`stages::broad_phase`, the step's broad phase on the body
/// arrays): the refused pair is missing, the allowed one present, and a body that refuses
/// everything has no pair at all. (The GPU sweep's own pair list is compared with the CPU
/// grid's in `gpu_broad_phase.rs`.)
#[test]
fn the_cpu_broad_phase_pair_list_leaves_out_refused_pairs() {
    use tumble::geometry::{Cuboid, Pose};
    use tumble::solver::{Body, BodyKind, BodyState, Material, stages};
    let cube = |x: Real, groups: CollisionGroups| {
        let mut b = Body::new(
            BodyKind::Dynamic,
            Cuboid::new(Vec3::repeat(0.5)),
            Pose::translation(x, 0.5, 0.0),
            1.0,
            Material::default(),
        )
        .unwrap();
        b.groups = groups;
        b
    };
    let mut floor = Body::new(
        BodyKind::Fixed,
        Cuboid::new(Vec3::new(5.0, 0.5, 5.0)),
        Pose::translation(0.0, -0.5, 0.0),
        1.0,
        Material::default(),
    )
    .unwrap();
    floor.groups = CollisionGroups::new(FLOOR_GROUP, u32::MAX);
    // Cubes 0.9 m apart overlap their neighbours: 1-2 and 2-3 overlap.
    let bodies = vec![
        floor,
        cube(0.0, DEBRIS),
        cube(0.9, CollisionGroups::ALL),
        cube(1.8, CollisionGroups::NONE),
    ];
    let states = vec![BodyState::default(); bodies.len()];
    let aabbs = stages::update_aabbs(&bodies, &states, 0.02, 1.0 / 60.0);
    let pairs = stages::broad_phase(&mut tumble_broad::KeptPairs::new(), &aabbs, &bodies);
    // Floor-debris refused by the debris' filter; floor-2 and debris-2 allowed; body 3
    // refuses everything (its overlaps with the floor and with 2 are dropped).
    assert_eq!(pairs, vec![(0, 2), (1, 2)]);
}

/// A constant force F on a free 8 kg cube in zero gravity: `v = F t / m`, and semi-implicit
/// Euler's `x = F/(2m) t^2 (1 + 1/n)` over n substeps; a constant torque on the same cube
/// (equal moments, so no gyroscopic term) spins it at `I^-1 tau t`. The force stays set across
/// steps until changed, and setting it to zero stops the acceleration. CPU, GPU and Hybrid
/// agree.
#[test]
fn constant_forces_and_torques_accelerate_as_newton_says() {
    let force = Vec3::new(8.0, 4.0, -12.0);
    let torque = Vec3::new(1.0, -2.0, 0.5);
    let mut results = Vec::new();
    for backend in backends() {
        let mut world = world(backend, Vec3::zeros());
        let pushed = world
            .add_body(BodyDesc::dynamic().cuboid(Vec3::repeat(1.0)))
            .unwrap();
        let spun = world
            .add_body(
                BodyDesc::dynamic()
                    .cuboid(Vec3::repeat(1.0))
                    .translation(0.0, 20.0, 0.0),
            )
            .unwrap();
        world.set_force(pushed, force).unwrap();
        world.set_torque(spun, torque).unwrap();
        assert_eq!(world.force(pushed).unwrap(), force);
        assert_eq!(world.torque(spun).unwrap(), torque);
        assert_eq!(world.torque(pushed).unwrap(), Vec3::zeros());
        let mass = f64::from(world.mass(pushed).unwrap());
        assert!(
            (mass - 8.0).abs() < 1e-5,
            "a 2 m cube of density 1: {mass} kg"
        );
        // Moments of a cube of side s: m s^2 / 6.
        let moment = mass * 4.0 / 6.0;
        for _ in 0..STEPS {
            world.step().unwrap();
        }
        let (h, n) = substeps(&world, STEPS);
        let t = h * n;
        let (p, v) = (
            position(&world, pushed),
            world.linear_velocity(pushed).unwrap(),
        );
        let w = world.angular_velocity(spun).unwrap();
        for k in 0..3 {
            let a = f64::from(force[k]) / mass;
            // Velocity: 360 f32 additions of a h (up to 4e-3 m/s): each rounds by at most
            // 1.2e-7 m/s at these speeds (< 2 m/s), 5e-5 in all; a force 0.1% off misses by
            // 1.5e-3 m/s.
            let dv = (f64::from(v[k]) - a * t).abs();
            assert!(dv < 5e-5, "{backend:?}: v[{k}] {} vs {}", v[k], a * t);
            // Position: the Euler sum to the same rounding (values below 1 m round by 6e-8
            // per update); the exact parabola is 1/n = 0.28% away (1.4 mm here), which the
            // bound separates from the scheme's own value.
            let x = euler_displacement(a, h, n);
            let dx = (f64::from(p[k]) - x).abs();
            assert!(dx < 5e-5, "{backend:?}: x[{k}] {} vs {x}", p[k]);
            let exact = a * t * t / 2.0;
            assert!((f64::from(p[k]) - exact).abs() <= (exact / n).abs() + 5e-5);
            let expected_w = f64::from(torque[k]) / moment * t;
            let dw = (f64::from(w[k]) - expected_w).abs();
            // Angular velocity: as the velocity above (spins below 1 rad/s).
            assert!(dw < 5e-5, "{backend:?}: w[{k}] {} vs {expected_w}", w[k]);
        }
        // The pushed cube does not turn, nor the spun one move.
        assert_eq!(world.angular_velocity(pushed).unwrap(), Vec3::zeros());
        assert_eq!(world.linear_velocity(spun).unwrap(), Vec3::zeros());
        // Removing the force and torque stops the acceleration: the velocities after one
        // more step are the ones before it, bit for bit (nothing else acts).
        world.set_force(pushed, Vec3::zeros()).unwrap();
        world.set_torque(spun, Vec3::zeros()).unwrap();
        world.step().unwrap();
        assert_eq!(world.linear_velocity(pushed).unwrap(), v);
        assert_eq!(world.angular_velocity(spun).unwrap(), w);
        results.push((backend, p, v, w));
    }
    let (_, p0, v0, w0) = results[0];
    for &(backend, p, v, w) in &results[1..] {
        // The same arithmetic on every backend (the force's `F (h / m)` and the torque's
        // `I^-1 (tau h)` in the same order): 1e-5 allows a few roundings of values near 1
        // per substep, and is 100 times smaller than what a force 0.1% off changes.
        let d = [(p - p0).amax(), (v - v0).amax(), (w - w0).amax()];
        assert!(
            d.iter().all(|&d| d < 1e-5),
            "{backend:?} differs from the CPU by {d:?} (position, velocity, spin)"
        );
    }
}

/// Gravity scales 0, 1, 2 and -1 on four cubes far apart: the first floats exactly where it
/// was, the others follow semi-implicit Euler under `scale * g`; a scale set with
/// `set_gravity_scale` after creation acts the same as one from the descriptor.
#[test]
fn gravity_scale_makes_bodies_float_fall_faster_or_rise() {
    let g = 9.81;
    for backend in backends() {
        let mut world = world(backend, Vec3::new(0.0, -g as Real, 0.0));
        let scales: [Real; 4] = [0.0, 1.0, 2.0, -1.0];
        let bodies: Vec<BodyHandle> = scales
            .iter()
            .enumerate()
            .map(|(k, &s)| {
                let desc = BodyDesc::dynamic().translation(5.0 * k as Real, 10.0, 0.0);
                // The scale of 2 is set on the world instead, after creation.
                let desc = if s == 2.0 {
                    desc
                } else {
                    desc.gravity_scale(s)
                };
                world.add_body(desc).unwrap()
            })
            .collect();
        world.set_gravity_scale(bodies[2], 2.0).unwrap();
        for (&h, &s) in bodies.iter().zip(&scales) {
            assert_eq!(world.gravity_scale(h).unwrap(), s);
        }
        for _ in 0..STEPS {
            world.step().unwrap();
        }
        let (h, n) = substeps(&world, STEPS);
        // Scale 0: no velocity is ever added, so the position is the initial one exactly.
        assert_eq!(position(&world, bodies[0]), Vec3::new(0.0, 10.0, 0.0));
        assert_eq!(world.linear_velocity(bodies[0]).unwrap(), Vec3::zeros());
        let mut drops = Vec::new();
        for (&b, &s) in bodies.iter().zip(&scales).skip(1) {
            let y = f64::from(position(&world, b).y);
            let expected = 10.0 - euler_displacement(f64::from(s) * g, h, n);
            // 1 mm: 360 f32 updates of positions up to 15 m and speeds up to 20 m/s round by
            // at most 1e-6 m and 1e-6 m/s each, 5e-4 m in all in the worst case; a scale 0.1%
            // off misses by 5 mm per unit of scale.
            assert!(
                (y - expected).abs() < 1e-3,
                "{backend:?}: scale {s}: y {y} vs {expected}"
            );
            drops.push(10.0 - y);
        }
        // Twice as fast: the scale-2 drop is twice the scale-1 drop, and -1 rises as far.
        assert!((drops[1] / drops[0] - 2.0).abs() < 1e-3, "{drops:?}");
        assert!((drops[2] / drops[0] + 1.0).abs() < 1e-3, "{drops:?}");
    }
}

/// User data is kept per body, through steps and through the removal of another body (which
/// moves the last body into the removed one's slot), and never read by the physics.
#[test]
fn user_data_round_trips_and_survives_steps_and_removals() {
    for backend in backends() {
        let mut world = world(backend, Vec3::new(0.0, -9.81, 0.0));
        let floor = world.add_body(floor_desc(5.0).user_data(7)).unwrap();
        let ids: Vec<u128> = (0..4).map(|k| u128::MAX - k).collect();
        let cubes: Vec<BodyHandle> = ids
            .iter()
            .enumerate()
            .map(|(k, &id)| {
                let desc = BodyDesc::dynamic().translation(1.5 * k as Real - 2.0, 0.5, 0.0);
                world.add_body(desc.user_data(id)).unwrap()
            })
            .collect();
        let plain = world.add_body(BodyDesc::dynamic().translation(0.0, 3.0, 0.0));
        let plain = plain.unwrap();
        assert_eq!(world.user_data(plain).unwrap(), 0, "the default");
        for _ in 0..10 {
            world.step().unwrap();
        }
        assert_eq!(world.user_data(floor).unwrap(), 7);
        world.set_user_data(cubes[1], 42).unwrap();
        world.remove_body(cubes[0]).unwrap();
        world.step().unwrap();
        assert_eq!(world.user_data(cubes[1]).unwrap(), 42);
        for (&h, &id) in cubes.iter().zip(&ids).skip(2) {
            assert_eq!(world.user_data(h).unwrap(), id, "{backend:?}");
        }
        assert_eq!(world.user_data(plain).unwrap(), 0);
        assert!(matches!(
            world.user_data(cubes[0]),
            Err(Error::RemovedHandle(_))
        ));
    }
}

/// Every bad value is an `Err` naming the field and the value, leaving every pose, velocity
/// and property as it was; an unknown handle is an `Err` too.
#[test]
fn bad_values_are_refused_by_name_and_change_nothing() {
    for backend in backends() {
        let mut world = world(backend, Vec3::new(0.0, -9.81, 0.0));
        world.add_body(floor_desc(5.0)).unwrap();
        let cube = world
            .add_body(BodyDesc::dynamic().translation(0.0, 0.5, 0.0))
            .unwrap();
        world.set_force(cube, Vec3::new(1.0, 0.0, 0.0)).unwrap();
        for _ in 0..5 {
            world.step().unwrap();
        }
        let before = snapshot(&world);
        let properties = |w: &World| {
            (
                w.force(cube).unwrap(),
                w.torque(cube).unwrap(),
                w.gravity_scale(cube).unwrap(),
                w.collision_groups(cube).unwrap(),
                w.body_count(),
            )
        };
        let kept = properties(&world);
        let nan = Real::NAN;
        let inf = Real::INFINITY;
        // The unit cube weighs 1 kg: 24 kN would add 400 m/s (MAX_SPEED) in one 1/60 s step.
        for bad in [
            Vec3::new(nan, 0.0, 0.0),
            Vec3::new(0.0, inf, 0.0),
            Vec3::new(0.0, 0.0, 1e21),
            Vec3::new(0.0, 24_100.0, 0.0),
        ] {
            let e = world.set_force(cube, bad).unwrap_err();
            assert_eq!(e.field(), Some("force"), "{e}");
            // The message quotes the rejected value.
            let quoted = format!("{:?}", [bad.x, bad.y, bad.z]);
            assert!(
                e.to_string().contains(&quoted),
                "{e} does not quote {quoted}"
            );
        }
        // Moments 1/6 kg m^2: 2.9 kN m would add more than pi/4 per substep of spin.
        for bad in [
            Vec3::new(0.0, nan, 0.0),
            Vec3::new(-inf, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 2900.0),
        ] {
            expect_field(world.set_torque(cube, bad), "torque");
        }
        for bad in [nan, inf, 10.5, -11.0] {
            let e = world.set_gravity_scale(cube, bad).unwrap_err();
            assert_eq!(e.field(), Some("gravity_scale"));
            assert!(e.to_string().contains(&format!("{bad:?}")), "{e}");
        }
        expect_field(
            world.add_body(BodyDesc::dynamic().gravity_scale(nan)),
            "gravity_scale",
        );
        let removed = world
            .add_body(BodyDesc::dynamic().translation(3.0, 0.5, 0.0))
            .unwrap();
        world.remove_body(removed).unwrap();
        let after_remove = snapshot(&world);
        assert!(matches!(
            world.set_force(removed, Vec3::zeros()),
            Err(Error::RemovedHandle(_))
        ));
        assert!(world.set_torque(removed, Vec3::zeros()).is_err());
        assert!(world.set_gravity_scale(removed, 1.0).is_err());
        assert!(
            world
                .set_collision_groups(removed, CollisionGroups::NONE)
                .is_err()
        );
        assert!(world.set_user_data(removed, 1).is_err());
        assert_eq!(snapshot(&world), after_remove, "{backend:?}");
        assert_eq!(properties(&world), kept, "{backend:?}");
        // The refused calls changed no bit of any pose or velocity (the add and remove in
        // between moved nothing either).
        assert_eq!(after_remove, before, "{backend:?}");
        // The accepted force is still set and the world still steps to finite states.
        assert_eq!(world.force(cube).unwrap(), Vec3::new(1.0, 0.0, 0.0));
        world.step().unwrap();
        let v = world.linear_velocity(cube).unwrap();
        assert!(v.iter().all(|c| c.is_finite()), "{backend:?}: {v}");
    }
}

/// FNV-1a over every pose bit of `world`.
fn pose_hash(world: &World) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    for &h in world.handles() {
        let p = world.pose(h).unwrap();
        let q = p.rotation.coords;
        for c in p.translation.vector.iter().chain(q.iter()) {
            hash = (hash ^ u64::from(c.to_bits())).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    hash
}

/// A pile with every property in use (groups, forces, torques, gravity scales): the same bits
/// run to run on each backend, and with 1 and 2 CPU threads.
#[test]
fn results_with_every_property_are_deterministic() {
    let run = |backend: Backend| {
        let mut world = world(backend, Vec3::new(0.0, -9.81, 0.0));
        world.add_body(floor_desc(10.0)).unwrap();
        for k in 0..24 {
            let (x, y) = ((k % 4) as Real * 1.05 - 1.5, 0.5 + (k / 4) as Real * 1.1);
            let mut desc = BodyDesc::dynamic().translation(x, y, 0.0);
            if k % 5 == 0 {
                desc = desc.collision_groups(DEBRIS);
            }
            if k % 3 == 0 {
                desc = desc.gravity_scale(0.5);
            }
            let h = world.add_body(desc).unwrap();
            if k % 4 == 1 {
                world.set_force(h, Vec3::new(3.0, 0.0, 1.0)).unwrap();
                world.set_torque(h, Vec3::new(0.0, 0.5, 0.0)).unwrap();
            }
        }
        for _ in 0..90 {
            world.step().unwrap();
        }
        pose_hash(&world)
    };
    let threads = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| run(Backend::Cpu))
    };
    assert_eq!(
        threads(1),
        threads(2),
        "CPU results depend on the thread count"
    );
    for backend in backends().into_iter().skip(1) {
        assert_eq!(run(backend), run(backend), "{backend:?} differs run to run");
    }
}
