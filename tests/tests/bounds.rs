//! The bounds of `tumble_solver::bounds` through the facade (docs/errors.md):
//!
//! - a step that would carry a body past a bound is refused with the body's handle and the
//!   quantity, leaving every pose and velocity bit and the step count as they were (Cpu with
//!   both solvers, with and without sleeping bodies, Hybrid, and Gpu, whose motion check
//!   finds it when the step is done and copies the device state back);
//! - seeded sequences of a few thousand world calls mixing extreme finite values (1e30,
//!   1e-30, subnormals, 1e6, -0.0) never panic, every `Err` leaves the world bitwise
//!   unchanged, and every accepted step leaves every pose and velocity finite.
//!
//! The GPU tests need a GPU (or lavapipe): without one they print "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble::prelude::*;
use tumble::solver::bounds::MAX_POSITION;
use tumble::{EffectSwitch, WorldConfig};
use tumble_gpu::GpuContext;
use tumble_tests::bad_input::{self, Snapshot, floor_and_cube, snapshot};
use tumble_tests::facade::add_floor;

fn have_gpu() -> bool {
    GpuContext::for_tests().is_some()
}

fn config(backend: Backend, solver: SolverConfig) -> WorldConfig {
    WorldConfig {
        backend,
        solver,
        ..Default::default()
    }
}

/// A floor, a cube resting on it, and a cube 2 m short of the position bound moving outward
/// at 300 m/s with no gravity: the first step moves it 5 m, 3 m past `MAX_POSITION`.
fn runaway_world(config: WorldConfig) -> (World, BodyHandle) {
    let mut world = World::new(WorldConfig {
        gravity: Vec3::zeros(),
        ..config
    })
    .unwrap();
    floor_and_cube(&mut world);
    let runaway = add_runaway(&mut world);
    (world, runaway)
}

/// Adds a cube 2 m short of the position bound moving outward at 300 m/s; its handle.
fn add_runaway(world: &mut World) -> BodyHandle {
    world
        .add_body(
            BodyDesc::dynamic()
                .translation(MAX_POSITION - 2.0, 0.0, 0.0)
                .linear_velocity(Vec3::new(300.0, 0.0, 0.0)),
        )
        .unwrap()
}

/// Asserts `result` is the refusal of a step naming `body` and `quantity`.
fn expect_refused(result: Result<(), Error>, body: BodyHandle, quantity: &str) {
    match result {
        Err(Error::InvalidStep {
            body: b,
            quantity: q,
            ..
        }) => assert_eq!((b, q), (body, quantity)),
        other => panic!("expected a refused step naming {body:?} {quantity}, got {other:?}"),
    }
}

/// The host backends refuse the step that would carry a body past `MAX_POSITION`, and
/// leave the world bit for bit as it was; the next step is refused the same way.
fn runaway_step_is_refused(backend: Backend, solver: SolverConfig) {
    let (mut world, runaway) = runaway_world(config(backend, solver));
    let before: Snapshot = snapshot(&world);
    let contacts_before = world.contacts().len();
    expect_refused(world.step(), runaway, "position");
    assert_eq!(snapshot(&world), before, "a refused step changed the world");
    assert_eq!(world.contacts().len(), contacts_before);
    expect_refused(world.step(), runaway, "position");
    assert_eq!(snapshot(&world), before);
    // Turned back, the body steps again: the refusal is about the state, not a stuck world.
    world
        .set_linear_velocity(runaway, Vec3::new(-300.0, 0.0, 0.0))
        .unwrap();
    world.step().unwrap();
    assert_eq!(world.step_count(), 1);
    assert!(world.pose(runaway).unwrap().translation.x < MAX_POSITION - 2.0);
}

#[test]
fn cpu_soft_step_refuses_a_step_past_the_position_bound() {
    runaway_step_is_refused(Backend::Cpu, SolverConfig::default());
}

#[test]
fn cpu_baumgarte_refuses_a_step_past_the_position_bound() {
    runaway_step_is_refused(Backend::Cpu, SolverConfig::baumgarte());
}

#[test]
fn hybrid_refuses_a_step_past_the_position_bound() {
    if have_gpu() {
        runaway_step_is_refused(Backend::Hybrid, SolverConfig::default());
    }
}

/// With sleep on and the resting cube asleep, the step runs on the gathered copy of the
/// bodies; the refusal must leave the host's bodies, and the sleeper, as they were.
#[test]
fn cpu_refuses_a_step_past_the_position_bound_while_bodies_sleep() {
    let mut cfg = config(Backend::Cpu, SolverConfig::default());
    cfg.effects.sleep = EffectSwitch::On;
    cfg.gravity = Vec3::new(0.0, -9.81, 0.0);
    let mut world = World::new(cfg).unwrap();
    let sleeper = floor_and_cube(&mut world);
    for _ in 0..300 {
        world.step().unwrap();
    }
    assert!(world.is_sleeping(sleeper).unwrap(), "the cube should rest");
    // A body far away, moving out fast and sideways, so gravity does not matter.
    let runaway = add_runaway(&mut world);
    let before = snapshot(&world);
    expect_refused(world.step(), runaway, "position");
    assert_eq!(snapshot(&world), before);
    assert!(world.is_sleeping(sleeper).unwrap());
}

/// A floor with a cube landing on it under gravity (so contacts and their warm starts carry
/// from step to step), and a cube 12 m short of the position bound moving outward at
/// 300 m/s: 5 m a step, so the third step would carry it past the bound.
fn world_with_late_runaway(backend: Backend) -> (World, BodyHandle, BodyHandle) {
    let mut cfg = config(backend, SolverConfig::default());
    cfg.gravity = Vec3::new(0.0, -9.81, 0.0);
    let mut world = World::new(cfg).unwrap();
    let cube = floor_and_cube(&mut world);
    let runaway = world
        .add_body(
            BodyDesc::dynamic()
                .translation(MAX_POSITION - 12.0, 0.0, 0.0)
                .linear_velocity(Vec3::new(300.0, 0.0, 0.0)),
        )
        .unwrap();
    (world, cube, runaway)
}

/// A step that would leave a body past `MAX_POSITION` is refused with `InvalidStep` naming
/// the body's handle and the quantity, and undone: on `Backend::Gpu` found by the GPU's motion
/// check when the step is done and the device state copied back from the checkpoint taken at
/// its start; on `Cpu` and `Hybrid` found by the host before anything is committed (Hybrid's
/// GPU pair history is not put back, and the twin shows it makes no difference). The world
/// is then bit for bit as before the step, and steps on exactly as a twin world that never
/// took the bad step (warm starts and pair matching included).
fn late_runaway_step_is_undone(backend: Backend) {
    let (mut world, cube, runaway) = world_with_late_runaway(backend);
    let (mut twin, _, _) = world_with_late_runaway(backend);
    for _ in 0..2 {
        world.step().unwrap();
        twin.step().unwrap();
    }
    // The cube touches the floor: the warm starts carried matter to the next steps.
    assert!(
        world
            .contacts()
            .iter()
            .any(|c| c.body_a == cube || c.body_b == cube),
        "the cube has no contact"
    );
    let before = snapshot(&world);
    let err = world.step().unwrap_err();
    let message = err.to_string();
    expect_refused(Err(err), runaway, "position");
    assert!(
        message.contains(&format!("{runaway:?}")) && message.contains("position"),
        "{message}"
    );
    assert_eq!(
        snapshot(&world),
        before,
        "the refused step changed the world"
    );
    assert_eq!(world.step_count(), 2);
    // Taken again unchanged, the step computes the same state and is refused the same way.
    expect_refused(world.step(), runaway, "position");
    assert_eq!(snapshot(&world), before);
    // Turned back, the body steps again, and the world computes what the twin (which never
    // took the bad step) computes from the same calls, bit for bit, warm starts included.
    for w in [&mut world, &mut twin] {
        w.set_linear_velocity(runaway, Vec3::new(-300.0, 0.0, 0.0))
            .unwrap();
        for _ in 0..3 {
            w.step().unwrap();
        }
    }
    assert_eq!(world.step_count(), 5);
    assert_eq!(snapshot(&world), snapshot(&twin), "{backend:?}");
    assert!(world.pose(runaway).unwrap().translation.x < MAX_POSITION - 12.0);
}

#[test]
fn cpu_undoes_a_step_past_the_position_bound_as_if_never_taken() {
    late_runaway_step_is_undone(Backend::Cpu);
}

#[test]
fn gpu_refuses_a_step_past_the_position_bound_and_undoes_it() {
    if have_gpu() {
        late_runaway_step_is_undone(Backend::Gpu);
    }
}

#[test]
fn hybrid_undoes_a_step_past_the_position_bound_with_its_gpu_pair_history_kept() {
    if have_gpu() {
        late_runaway_step_is_undone(Backend::Hybrid);
    }
}

/// Values the random calls draw from: ordinary ones, and extreme finite ones on both sides
/// of every bound.
const VALUES: &[Real] = &[
    0.0, -0.0, 0.5, 1.0, -1.0, 2.0, 10.0, -30.0, 1e3, 1e6, -1e6, 1e30, -1e30, 1e-30, 1e-40, -1e-40,
    3e38, 399.0, 401.0, 32_000.0,
];

fn value(rng: &mut ChaCha8Rng) -> Real {
    if rng.random_bool(0.5) {
        rng.random_range(-3.0..3.0)
    } else {
        VALUES[rng.random_range(0..VALUES.len())]
    }
}

fn vector(rng: &mut ChaCha8Rng) -> Vec3 {
    Vec3::new(value(rng), value(rng), value(rng))
}

fn pose(rng: &mut ChaCha8Rng) -> Pose {
    let mut p = Pose::translation(value(rng), value(rng), value(rng));
    if rng.random_bool(0.8) {
        p.rotation = Rot::from_euler_angles(value(rng), value(rng), value(rng));
    }
    if rng.random_bool(0.1) {
        p.rotation = Rot::new_unchecked(tumble::nalgebra::Quaternion::new(
            value(rng),
            value(rng),
            value(rng),
            value(rng),
        ));
    }
    p
}

fn desc(rng: &mut ChaCha8Rng) -> BodyDesc {
    let base = match rng.random_range(0..6) {
        0 => BodyDesc::fixed(),
        1 => BodyDesc::kinematic(),
        _ => BodyDesc::dynamic(),
    };
    let mut d = base.pose(pose(rng));
    if rng.random_bool(0.5) {
        d = d.cuboid(vector(rng).map(Real::abs));
    }
    if rng.random_bool(0.5) {
        d = d.density(value(rng).abs());
    }
    if rng.random_bool(0.3) {
        d = d
            .friction(value(rng).abs())
            .restitution(rng.random_range(0.0..1.0));
    }
    if rng.random_bool(0.5) {
        d = d.linear_velocity(vector(rng));
    }
    if rng.random_bool(0.5) {
        d = d.angular_velocity(vector(rng));
    }
    if rng.random_bool(0.2) {
        d = d
            .linear_damping(value(rng).abs())
            .angular_damping(value(rng).abs());
    }
    d
}

/// Every pose and velocity of `world` is finite.
fn all_finite(world: &World) -> bool {
    world.handles().iter().all(|&h| {
        let p = world.pose(h).unwrap();
        let v = world.linear_velocity(h).unwrap();
        let w = world.angular_velocity(h).unwrap();
        p.translation.vector.iter().all(|c| c.is_finite())
            && p.rotation.coords.iter().all(|c| c.is_finite())
            && v.iter().chain(w.iter()).all(|c| c.is_finite())
    })
}

/// What one random sequence did.
#[derive(Debug, Default)]
struct Tally {
    accepted: usize,
    refused: usize,
    steps: usize,
    refused_steps: usize,
}

/// `calls` seeded random calls on a world of `backend` with a floor: each `Err` must leave
/// the world bit for bit as it was, each accepted step every pose and velocity finite.
fn random_calls(backend: Backend, seed: u64, calls: usize) -> Tally {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut world = World::new(config(backend, SolverConfig::default())).unwrap();
    add_floor(&mut world, 20.0);
    let mut tally = Tally::default();
    for call in 0..calls {
        let handles = world.handles().to_vec();
        let h = handles[rng.random_range(0..handles.len())];
        let before = snapshot(&world);
        let kind = rng.random_range(0..10);
        let result = match kind {
            0 if handles.len() < 24 => world.add_body(desc(&mut rng)).map(|_| ()),
            1 if handles.len() > 4 => world.remove_body(h),
            2 => world.set_pose(h, pose(&mut rng)),
            3 => world.set_linear_velocity(h, vector(&mut rng)),
            4 => world.set_angular_velocity(h, vector(&mut rng)),
            5 => world.apply_impulse(h, vector(&mut rng), Point3::from(vector(&mut rng))),
            6 => world.set_kinematic_target(h, pose(&mut rng)),
            _ => world.step(),
        };
        let stepped =
            kind >= 7 || (kind == 0 && handles.len() >= 24) || (kind == 1 && handles.len() <= 4);
        match result {
            Err(e) => {
                tally.refused += 1;
                tally.refused_steps += usize::from(stepped);
                assert_eq!(
                    snapshot(&world),
                    before,
                    "seed {seed}, call {call}: the refused call ({e}) changed the world"
                );
            }
            Ok(()) => {
                tally.accepted += 1;
                if stepped {
                    tally.steps += 1;
                    assert!(
                        all_finite(&world),
                        "seed {seed}, call {call}: an accepted step left a non-finite state"
                    );
                }
            }
        }
    }
    tally
}

#[test]
fn cpu_random_calls_with_extreme_values_keep_the_world_finite() {
    // 8 sequences of 500 calls (4000 in all), seeds fixed so a failure reproduces.
    let mut total = Tally::default();
    for seed in 0..8 {
        let t = random_calls(Backend::Cpu, 0x5eed_0000 + seed, 500);
        total.accepted += t.accepted;
        total.refused += t.refused;
        total.steps += t.steps;
        total.refused_steps += t.refused_steps;
    }
    // The mix must exercise both sides: many refusals of extreme values, and many steps of
    // the worlds the accepted calls built (a test that refused everything would prove
    // nothing).
    assert!(total.refused > 500, "{total:?}");
    assert!(total.steps > 500, "{total:?}");
    println!("{total:?}");
}

#[test]
fn gpu_random_calls_with_extreme_values_keep_the_world_finite() {
    if !have_gpu() {
        return;
    }
    let t = random_calls(Backend::Gpu, 0x5eed_1000, 300);
    assert!(t.refused > 30 && t.steps > 30, "{t:?}");
    println!("{t:?}");
}

#[test]
fn gpu_out_of_bound_updates_are_rejected() {
    if have_gpu() {
        bad_input::out_of_bound_updates_are_rejected(Backend::Gpu, SolverConfig::default());
    }
}

#[test]
fn hybrid_out_of_bound_updates_are_rejected() {
    if have_gpu() {
        bad_input::out_of_bound_updates_are_rejected(Backend::Hybrid, SolverConfig::default());
    }
}

/// With 8 substeps the 300 rad/s spin (what the 100 N s impulse at the cube's edge gives) is
/// within the bound that 6 substeps refuse it by (pi/4 rad per substep: 8 * 60 * pi/4 = 377
/// rad/s), so that call must go through, and every other case is still refused by name.
#[test]
fn out_of_bound_updates_at_eight_substeps_accept_the_faster_spin() {
    let solver = SolverConfig {
        substeps: 8,
        ..SolverConfig::default()
    };
    bad_input::out_of_bound_updates_are_rejected(Backend::Cpu, solver);
}
