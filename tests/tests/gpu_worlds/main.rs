//! Several independent worlds in one `GpuWorld` (`set_bodies_in_worlds`): one set of buffers,
//! one set of dispatches per step, and each world's bodies end bitwise equal to the same
//! world's bodies stepped alone. Every world stands at the same place, so a pair formed across
//! worlds, a sweep that ran past its world or a constraint colored by another world's
//! numbering would change a bit somewhere.
//!
//! Needs a GPU (or lavapipe): without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.

mod solve;
mod sorts;
mod uploads;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Cuboid, Pose, Real, Vec3};
use tumble_gpu::GpuContext;
use tumble_gpu::layout::GpuPose;
use tumble_gpu::solver::path::{WORLD_GROUP_BODIES, WORLDS_PACK_MIN_BODIES, world_groups};
use tumble_gpu::solver::{FusedMemory, SolvePath, WorldGrouping};
use tumble_gpu::step::{GpuWorld, GpuWorldConfig, PathPolicy, ReadRequest};
use tumble_solver::{Body, BodyKind, BodyState, Material};
use tumble_tests::gpu_solver_util::{floor, pose_bits};
use tumble_tests::scene_support::random_vec;

/// One small world: a floor and, by `seed % 4`, a column, a small pyramid, boxes of mixed
/// sizes dropped with spins, or a box sliding along the floor into a wall. Every world has
/// friction and no restitution, so the batch needs the same effects as each world alone.
fn small_world(seed: u64) -> (Vec<Body>, Vec<BodyState>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let material = Material {
        friction: 0.6,
        restitution: 0.0,
    };
    let cube = |p: Vec3, h: Vec3, spin: Vec3| {
        Body::new(
            BodyKind::Dynamic,
            Cuboid::new(h),
            Pose::new(p, spin),
            1.0,
            material,
        )
        .unwrap()
    };
    let mut bodies = vec![floor(material)];
    let mut states = Vec::new();
    match seed % 4 {
        0 => {
            let height = rng.random_range(3..8);
            for k in 0..height {
                let x = rng.random_range(-0.05..0.05);
                bodies.push(cube(
                    Vec3::new(x, 0.5 + k as Real * 1.001, 0.0),
                    Vec3::repeat(0.5),
                    Vec3::zeros(),
                ));
            }
        }
        1 => {
            let layers = rng.random_range(2..5);
            for level in 0..layers {
                for i in 0..(layers - level) {
                    let x = i as Real * 1.02 - (layers - 1 - level) as Real * 0.51;
                    bodies.push(cube(
                        Vec3::new(x, 0.5 + level as Real, 0.0),
                        Vec3::repeat(0.5),
                        Vec3::zeros(),
                    ));
                }
            }
        }
        2 => {
            for k in 0..rng.random_range(3..7) {
                let p = Vec3::new(
                    rng.random_range(-1.0..1.0),
                    1.5 + 1.2 * k as Real,
                    rng.random_range(-1.0..1.0),
                );
                bodies.push(cube(
                    p,
                    random_vec(&mut rng, 0.2..0.6),
                    random_vec(&mut rng, -1.0..1.0),
                ));
            }
        }
        _ => {
            bodies.push(
                Body::new(
                    BodyKind::Fixed,
                    Cuboid::new(Vec3::new(0.25, 1.0, 2.0)),
                    Pose::translation(3.0, 1.0, 0.0),
                    1.0,
                    material,
                )
                .unwrap(),
            );
            bodies.push(cube(
                Vec3::new(-2.0, 0.4, 0.0),
                Vec3::new(0.4, 0.4, 0.3),
                Vec3::zeros(),
            ));
        }
    }
    states.resize(bodies.len(), BodyState::default());
    if seed % 4 == 3 {
        // The slider, sent toward the wall fast enough to reach it before friction stops it.
        let last = states.len() - 1;
        states[last] = BodyState::moving(
            Vec3::new(rng.random_range(6.0..8.0), 0.0, 0.0),
            Vec3::zeros(),
        );
    }
    (bodies, states)
}

/// The worlds `scenes` laid end to end, as `set_bodies_in_worlds` takes them: bodies,
/// states, each body's world, and each world's first body.
fn concat(
    scenes: &[(Vec<Body>, Vec<BodyState>)],
) -> (Vec<Body>, Vec<BodyState>, Vec<u32>, Vec<usize>) {
    let (mut bodies, mut states, mut worlds, mut firsts) = (vec![], vec![], vec![], vec![]);
    for (w, (b, s)) in scenes.iter().enumerate() {
        firsts.push(bodies.len());
        bodies.extend_from_slice(b);
        states.extend_from_slice(s);
        worlds.extend(std::iter::repeat_n(w as u32, b.len()));
    }
    (bodies, states, worlds, firsts)
}

/// Steps a world of `bodies` (in `worlds`, or all in world 0 when empty) and reads the poses.
fn run(
    ctx: &GpuContext,
    bodies: &[Body],
    states: &[BodyState],
    worlds: &[u32],
    steps: usize,
) -> Vec<GpuPose> {
    run_on(
        ctx,
        GpuWorldConfig::default(),
        bodies,
        states,
        worlds,
        steps,
    )
}

/// [`run`] with `config` (its solver path and where the fused paths keep the bodies).
fn run_on(
    ctx: &GpuContext,
    config: GpuWorldConfig,
    bodies: &[Body],
    states: &[BodyState],
    worlds: &[u32],
    steps: usize,
) -> Vec<GpuPose> {
    let mut world = GpuWorld::new(ctx, config).unwrap();
    world.set_bodies_in_worlds(bodies, states, worlds).unwrap();
    for _ in 0..steps {
        world.step().unwrap();
    }
    let snapshot = world.read_now(ReadRequest::MOTION).unwrap();
    for p in &snapshot.poses {
        assert!(
            p.position.iter().chain(&p.rotation).all(|c| c.is_finite()),
            "{p:?}"
        );
    }
    snapshot.poses
}

/// Steps `count` small worlds as one batch and each alone, and requires every body of every
/// world to end with the same bits both ways. The batch runs with `config` (on the default,
/// small worlds choose one fused workgroup per world, `SolvePath::Worlds`); the worlds alone
/// run with the default config.
fn batch_matches_alone(count: u64, steps: usize, config: GpuWorldConfig) {
    let scenes: Vec<_> = (0..count).map(small_world).collect();
    scenes_match_alone(&scenes, steps, config);
}

/// [`batch_matches_alone`] on the worlds `scenes`.
fn scenes_match_alone(
    scenes: &[(Vec<Body>, Vec<BodyState>)],
    steps: usize,
    config: GpuWorldConfig,
) {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let count = scenes.len();
    let (bodies, states, worlds, _) = concat(scenes);
    let batch = run_on(&ctx, config, &bodies, &states, &worlds, steps);
    let mut first = 0;
    let mut moved = 0.0;
    for (w, (b, s)) in scenes.iter().enumerate() {
        let alone = run(&ctx, b, s, &[], steps);
        for (i, pose) in alone.iter().enumerate() {
            let fused = &batch[first + i];
            assert_eq!(
                pose_bits(pose),
                pose_bits(fused),
                "world {w}, body {i}: alone {pose:?}, in the batch {fused:?}"
            );
            let start = b[i].pose.translation.vector;
            let end = Vec3::new(pose.position[0], pose.position[1], pose.position[2]);
            moved += (end - start).norm();
        }
        first += b.len();
    }
    // The comparison means something only if the worlds did something: the dropped boxes
    // fall, the sliders slide (a world at rest from the start would match trivially).
    assert!(
        moved > 0.5 * count as Real,
        "the worlds hardly moved: {moved} m in all"
    );
}
