//! Sleep on the GPU world, whole steps: a settled pool falls asleep and then stops changing bit
//! for bit, a box dropped on one of two sleeping piles wakes that pile only (which sleeps again
//! with the box), the host's pose, velocity, impulse and wake calls wake a sleeping island, a
//! moving kinematic slab wakes and pushes a sleeping cube, and two runs sleep alike. With
//! sleep on, a scene that has not fallen asleep yet steps bit for bit as with sleep off (the
//! stage only watches until an island sleeps); with sleep off nothing of the stage is recorded
//! at all, which the existing determinism and effect tests cover. The stage against its CPU
//! twins is in `gpu_sleep_stage.rs`.
//!
//! Needs a GPU (or lavapipe): without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.

mod determinism;
mod waking;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Cuboid, Point3, Pose, Real, Vec3};
use tumble_gpu::GpuContext;
use tumble_gpu::layout::GpuPose;
use tumble_gpu::solver::Effects;
use tumble_gpu::step::{GpuWorld, GpuWorldConfig, ReadRequest, Snapshot};
use tumble_solver::{Body, BodyKind, BodyState, Material, TIME_TO_SLEEP};
use tumble_tests::gpu_solver_util::{pose_bits, velocity_bits};

/// The world's step, s (the default 60 Hz).
const DT: Real = 1.0 / 60.0;

/// Half extent of the cubes of the scenes, m.
const HALF: Real = 0.25;

/// Everything a readback can hold except the contacts.
const STATE: ReadRequest = ReadRequest {
    poses: true,
    velocities: true,
    contacts: false,
    sleeping: true,
    summary: false,
};

/// A cube of half extent [`HALF`] of `kind` at `pose`.
fn body(kind: BodyKind, pose: Pose) -> Body {
    Body::new(
        kind,
        Cuboid::new(Vec3::repeat(HALF)),
        pose,
        1.0,
        Material::default(),
    )
    .unwrap()
}

/// A 40 m floor whose top is at y = 0.
fn floor() -> Body {
    tumble_tests::gpu_solver_util::floor(Material::default())
}

/// A cube resting (1 mm above contact, so nothing starts overlapped) at layer `layer` of a
/// column standing at (x, z).
fn cube(x: Real, layer: usize, z: Real) -> Body {
    let y = HALF + layer as Real * 2.0 * HALF + 0.001 * (layer + 1) as Real;
    body(BodyKind::Dynamic, Pose::translation(x, y, z))
}

/// A `side` x `side` block of columns `layers` high centred at (x, z), 2 cm between columns.
fn pile(x: Real, z: Real, side: usize, layers: usize) -> Vec<Body> {
    let pitch = 2.0 * HALF + 0.02;
    let offset = (side as Real - 1.0) * pitch / 2.0;
    let mut out = Vec::new();
    for layer in 0..layers {
        for i in 0..side {
            for k in 0..side {
                let (cx, cz) = (
                    x + i as Real * pitch - offset,
                    z + k as Real * pitch - offset,
                );
                out.push(cube(cx, layer, cz));
            }
        }
    }
    out
}

/// A GPU world with `bodies` at rest and sleep on.
fn sleeping_world(ctx: &GpuContext, bodies: &[Body]) -> GpuWorld {
    sleeping_world_with(ctx, bodies, GpuWorldConfig::default())
}

/// [`sleeping_world`] with `config`.
fn sleeping_world_with(ctx: &GpuContext, bodies: &[Body], config: GpuWorldConfig) -> GpuWorld {
    let mut world = GpuWorld::new(ctx, config).unwrap();
    world
        .set_bodies(bodies, &vec![BodyState::default(); bodies.len()])
        .unwrap();
    set_sleep(&mut world, true);
    assert!(world.effects().sleep);
    world
}

/// Turns sleep on or off in `world`, the other effects as they are.
fn set_sleep(world: &mut GpuWorld, sleep: bool) {
    let effects = Effects {
        sleep,
        ..world.effects()
    };
    world.set_effects(effects).unwrap();
}

/// Steps until every dynamic body in `bodies` sleeps, at most `limit` steps; the snapshot
/// then, and the steps taken.
fn step_until_asleep(world: &mut GpuWorld, which: &[usize], limit: usize) -> (Snapshot, usize) {
    for steps in 1..=limit {
        world.step().unwrap();
        let snap = world.read_now(STATE).unwrap();
        if which.iter().all(|&i| snap.sleeping[i]) {
            return (snap, steps);
        }
    }
    let snap = world.read_now(STATE).unwrap();
    let awake: Vec<usize> = which
        .iter()
        .copied()
        .filter(|&i| !snap.sleeping[i])
        .collect();
    panic!("not asleep after {limit} steps: bodies {awake:?}");
}

/// Bitwise equality of poses.
fn same_bits(a: &GpuPose, b: &GpuPose) -> bool {
    pose_bits(a) == pose_bits(b)
}

/// Steps a block dropped from a few centimetres needs at most to fall asleep: the drops end
/// within 0.15 s (9 cm at g), the contacts settle within about a second (the pool below,
/// with seeds 5, 6 and 7, sleeps at step 81 to 83, 1.4 s), then every body must rest for
/// TIME_TO_SLEEP. Twice 1.5 s, 3 s, is the bound.
const SETTLE_STEPS: usize = (2.0 * (1.0 + TIME_TO_SLEEP) / DT) as usize;

/// The pool of [`a_settled_pool_falls_asleep_and_then_stops_changing`]: a 6 x 6 pool two cubes
/// deep on a floor, each cube raised 3 cm per layer, shifted sideways by up to 8 mm and tilted
/// by up to 0.02 rad about each axis (seeded), so that the cubes fall, land unevenly and settle.
fn uneven_pool() -> Vec<Body> {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut bodies = vec![floor()];
    for mut b in pile(0.0, 0.0, POOL_SIDE, POOL_LAYERS) {
        let layer = (b.pose.translation.y / (2.0 * HALF)).floor();
        let shift = Vec3::new(
            rng.random_range(-0.008..0.008),
            0.03 * (layer + 1.0),
            rng.random_range(-0.008..0.008),
        );
        let tilt = Vec3::from_fn(|_, _| rng.random_range(-0.02..0.02));
        b.pose = Pose::new(b.pose.translation.vector + shift, tilt);
        bodies.push(b);
    }
    bodies
}

/// Columns per side of the pool.
const POOL_SIDE: usize = 6;
/// Cubes per column of the pool. (Three-high columns of these 0.5 m cubes, shifted by a few
/// millimetres, rock at about 0.07 m/s indefinitely on the CPU and GPU solvers alike with the
/// default solver settings, so they would never sleep: a solver matter, not a sleep one.)
const POOL_LAYERS: usize = 2;
