//! `WorldBatch`: many worlds stepped together give, world by world, the same bits as each
//! world stepped alone with the same calls, through per-world actions, added and removed
//! bodies, saved states and resets; a reset touches no other world; bad actions and reads
//! return errors and change nothing.
//!
//! Every comparison is bitwise (`f32::to_bits`): the batch steps each world with the same
//! code as a lone `World`, and the step's result does not depend on the thread count or on
//! the other worlds, so any difference at all is a bug (a world stepped twice, an action
//! lost or applied to the wrong world, a reset that kept something of the old run).
//!
//! The GPU tests need an adapter (lavapipe in CI): without one they print "skipped" and pass,
//! unless `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.
//!
//! Run time on 2 cores (opt-level 3 test profile): about 5 s for the CPU tests; the GPU ones,
//! on lavapipe, a few hundred lavapipe steps in all (tens of seconds on a loaded machine).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble::prelude::*;
use tumble::scenes::builders::{self, common::floor};
use tumble::scenes::{BodyKind as SceneKind, BodySpec, Scene};
use tumble::{
    Action, ActionKind, BatchError, POSE_FLOATS, VELOCITY_FLOATS, WorldBatch, WorldId, WorldSpec,
};

/// Bad actions, reads and worlds: errors that name what is wrong and change nothing.
mod bad_input;

/// The GPU batch's resets and its worlds that come and go.
mod gpu;

/// A scene of boxes of mixed sizes, densities and spins dropped on the floor, and one
/// kinematic paddle sweeping through them (the target of the kinematic actions).
fn mixed(seed: u64, n: usize) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut scene = Scene::new(
        format!("mixed_{seed}"),
        "Boxes of mixed sizes and a paddle.",
    );
    scene.bodies.push(floor());
    let mut paddle = BodySpec::dynamic([1.0, 0.2, 0.2], [-3.0, 0.4, 0.0]);
    paddle.kind = SceneKind::Kinematic;
    scene.bodies.push(paddle);
    for k in 0..n {
        let h = [
            rng.random_range(0.15..0.7),
            rng.random_range(0.15..0.7),
            rng.random_range(0.15..0.7),
        ];
        let p = [
            rng.random_range(-2.0..2.0),
            1.0 + 1.5 * k as Real,
            rng.random_range(-1.5..1.5),
        ];
        let mut b = BodySpec::dynamic(h, p);
        b.density = rng.random_range(0.5..4.0);
        b.angular_velocity = [
            rng.random_range(-2.0..2.0),
            rng.random_range(-2.0..2.0),
            rng.random_range(-2.0..2.0),
        ];
        scene.bodies.push(b);
    }
    scene
}

/// `n` different small scenes: columns, pyramids, walls, dominoes, ramps, mass ratios, a
/// spinning box and mixed piles, some with their own gravity and time step.
fn scenes(n: usize) -> Vec<Scene> {
    (0..n)
        .map(|i| {
            let mut s = match i % 8 {
                0 => builders::stack(3 + i % 6),
                1 => builders::pyramid(2 + i % 3),
                2 => builders::dominoes(4 + i % 5),
                3 => builders::friction_ramp(10.0 + i as Real, 0.2 + 0.01 * i as Real),
                4 => builders::wall(2 + i % 3, 2 + i % 2),
                5 => match i % 3 {
                    0 => builders::mass_ratio(),
                    1 => builders::wide_on_small(),
                    _ => builders::spinning_box(),
                },
                _ => mixed(i as u64, 3 + i % 5),
            };
            // Per-world gravity and time step: every third world is on a smaller planet,
            // every fifth steps at 120 Hz.
            if i % 3 == 1 {
                s.gravity = [0.3, -6.0 - 0.1 * i as Real, 0.0];
            }
            if i % 5 == 2 {
                s.dt = 1.0 / 120.0;
            }
            s
        })
        .collect()
}

/// A call made on one world, as the batch makes it; a lone `World` replays the same list.
#[derive(Clone, Debug)]
enum Event {
    Step,
    Act(BodyHandle, ActionKind),
    Add(BodyDesc),
    Remove(BodyHandle),
}

/// What the test expects of one world: the calls of its timeline (a reset drops those after
/// the saved position, which `saved` holds).
#[derive(Clone, Debug, Default)]
struct Timeline {
    events: Vec<Event>,
    saved: usize,
}

/// The scene replayed in a lone world: `World::from_scene` and the timeline's calls.
fn replay_alone(scene: &Scene, backend: Backend, events: &[Event]) -> World {
    let config = WorldConfig {
        backend,
        ..WorldConfig::default()
    };
    let (mut world, _) = World::from_scene(scene, config).unwrap();
    for e in events {
        match e {
            Event::Step => world.step().unwrap(),
            Event::Act(h, ActionKind::Impulse { impulse, point }) => {
                world.apply_impulse(*h, *impulse, *point).unwrap()
            }
            Event::Act(h, ActionKind::SetVelocity { linear, angular }) => {
                world.set_linear_velocity(*h, *linear).unwrap();
                world.set_angular_velocity(*h, *angular).unwrap();
            }
            Event::Act(h, ActionKind::KinematicTarget { target }) => {
                world.set_kinematic_target(*h, *target).unwrap()
            }
            Event::Add(desc) => {
                world.add_body(*desc).unwrap();
            }
            Event::Remove(h) => world.remove_body(*h).unwrap(),
        }
    }
    world
}

/// Every body's pose and velocity bits, in the world's order.
fn world_bits(world: &World) -> Vec<u32> {
    let mut out = Vec::new();
    for &h in world.handles() {
        let p = world.pose(h).unwrap();
        let (t, q) = (p.translation.vector, p.rotation.coords);
        let v = world.linear_velocity(h).unwrap();
        let w = world.angular_velocity(h).unwrap();
        for x in [
            t.x, t.y, t.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, w.x, w.y, w.z,
        ] {
            out.push(x.to_bits());
        }
    }
    out
}

/// One world's pose and velocity bits as the batch reads them (the reads under test), in
/// the layout of [`world_bits`].
fn batch_bits(batch: &WorldBatch, id: WorldId) -> Vec<u32> {
    let n = batch.body_count(id).unwrap();
    let mut poses = vec![0.0; n * POSE_FLOATS];
    let mut vels = vec![0.0; n * VELOCITY_FLOATS];
    batch.read_poses(id, &mut poses).unwrap();
    batch.read_velocities(id, &mut vels).unwrap();
    poses
        .chunks(POSE_FLOATS)
        .zip(vels.chunks(VELOCITY_FLOATS))
        .flat_map(|(p, v)| p.iter().chain(v).map(|x| x.to_bits()).collect::<Vec<_>>())
        .collect()
}

/// The actions of step `s` for world `w` (index `k` in the batch): on one step in `every`,
/// an impulse on some dynamic bodies, a new velocity, or a paddle target, drawn from a
/// generator seeded by `(k, s)` so the script is fixed.
fn actions_for(batch: &WorldBatch, id: WorldId, k: usize, s: usize, every: u32) -> Vec<Action> {
    let mut rng = ChaCha8Rng::seed_from_u64((k as u64) << 32 | s as u64);
    if rng.random_range(0..every) != 0 {
        return Vec::new();
    }
    let world = batch.world(id).unwrap();
    let mut out = Vec::new();
    for &h in world.handles() {
        match world.kind(h).unwrap() {
            BodyKind::Dynamic if rng.random_range(0..3) == 0 => {
                let m = world.mass(h).unwrap();
                let p = world.pose(h).unwrap().translation.vector;
                let dir = Vec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(0.0..1.0),
                    rng.random_range(-1.0..1.0),
                );
                let kind = if rng.random_range(0..4) == 0 {
                    ActionKind::SetVelocity {
                        linear: dir * 2.0,
                        angular: Vec3::new(0.0, rng.random_range(-3.0..3.0), 0.0),
                    }
                } else {
                    // An off-centre impulse of up to 2 m/s, so it spins the box too.
                    ActionKind::Impulse {
                        impulse: dir * (2.0 * m),
                        point: Point3::from(p + Vec3::new(0.1, 0.2, -0.1)),
                    }
                };
                out.push(Action {
                    world: id,
                    body: h,
                    kind,
                });
            }
            BodyKind::Kinematic => {
                let p = world.pose(h).unwrap();
                let mut target = p;
                target.translation.vector.x += 0.05;
                target.rotation = Rot::from_euler_angles(0.0, 0.02, 0.0) * p.rotation;
                out.push(Action::kinematic_target(id, h, target));
            }
            _ => {}
        }
    }
    out
}

/// Runs `scenes` in a batch on `backend` for `steps` steps with the scripted actions, a body
/// added and one removed in some worlds, states saved at a third of the run and resets at
/// two thirds (to the saved state, or to the start for worlds never saved), then checks each
/// world bitwise against the scene replayed alone with the calls the world kept. Actions
/// come on one step in `every`. Without `mid_run_saves` no state is saved after the start:
/// on `Backend::Gpu` a reset restarts a world cold from its saved bodies (its contacts are
/// not kept), which a lone world replayed from the start only matches for the start.
fn batch_matches_worlds_alone(
    backend: Backend,
    scenes: &[Scene],
    steps: usize,
    every: u32,
    mid_run_saves: bool,
) {
    let config = WorldConfig {
        backend,
        ..WorldConfig::default()
    };
    let mut batch = WorldBatch::from_scenes(scenes, config).unwrap();
    let ids = batch.ids();
    assert_eq!(ids.len(), scenes.len());
    if backend == Backend::Gpu {
        // One device world per distinct config (here, per gravity and time step).
        let mut configs: Vec<([Real; 3], Real)> = Vec::new();
        for s in scenes {
            if !configs.contains(&(s.gravity, s.dt)) {
                configs.push((s.gravity, s.dt));
            }
        }
        assert_eq!(batch.device_worlds(), configs.len());
    }
    let mut timelines = vec![Timeline::default(); scenes.len()];
    let mut moved_by_actions = 0usize;
    for s in 0..steps {
        let mut actions = Vec::new();
        for (k, &id) in ids.iter().enumerate() {
            let a = actions_for(&batch, id, k, s, every);
            moved_by_actions += a.len();
            timelines[k]
                .events
                .extend(a.iter().map(|a| Event::Act(a.body, a.kind)));
            actions.extend(a);
        }
        batch.apply_actions(&actions).unwrap();
        for (k, &id) in ids.iter().enumerate() {
            if s == steps / 6 && k % 3 == 0 {
                let desc = BodyDesc::dynamic()
                    .cuboid(Vec3::new(0.3, 0.2, 0.4))
                    .translation(0.5, 6.0, 0.2);
                batch.add_body(id, desc).unwrap();
                timelines[k].events.push(Event::Add(desc));
            }
            if s == steps / 4 && k % 5 == 0 {
                let h = *batch.handles(id).unwrap().last().unwrap();
                batch.remove_body(id, h).unwrap();
                timelines[k].events.push(Event::Remove(h));
            }
            if mid_run_saves && s == steps / 3 && k % 2 == 0 {
                batch.save_state(id).unwrap();
                timelines[k].saved = timelines[k].events.len();
            }
        }
        if s == 2 * steps / 3 {
            let reset: Vec<WorldId> = ids.iter().copied().step_by(3).collect();
            batch.reset(&reset).unwrap();
            for k in (0..ids.len()).step_by(3) {
                let t = &mut timelines[k];
                t.events.truncate(t.saved);
                // Worlds never saved went back to their start: a reset truncates to 0.
                assert_eq!(
                    batch.step_count(ids[k]).unwrap(),
                    t.events.iter().filter(|e| matches!(e, Event::Step)).count() as u64
                );
            }
        }
        batch.step().unwrap();
        for t in &mut timelines {
            t.events.push(Event::Step);
        }
    }
    // The script did act: a run where no action landed would compare idle worlds.
    assert!(
        moved_by_actions > scenes.len(),
        "{moved_by_actions} actions"
    );

    // The lone worlds step on one thread, the batch on all: equal bits also show the step
    // does not depend on the thread count.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut packed = vec![0.0; batch.all_poses_len()];
    batch.read_all_poses(&mut packed).unwrap();
    let mut offset = 0;
    for (k, (&id, scene)) in ids.iter().zip(scenes).enumerate() {
        let alone = pool.install(|| replay_alone(scene, backend, &timelines[k].events));
        assert_eq!(
            batch_bits(&batch, id),
            world_bits(&alone),
            "world {k} ({}) differs from the scene stepped alone",
            scene.name
        );
        assert_eq!(batch.step_count(id).unwrap(), alone.step_count());
        // The packed read holds the same poses, world after world.
        let n = batch.body_count(id).unwrap() * POSE_FLOATS;
        let mut own = vec![0.0; n];
        batch.read_poses(id, &mut own).unwrap();
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&packed[offset..offset + n]), bits(&own), "world {k}");
        offset += n;
    }
    assert_eq!(offset, packed.len());
}

#[test]
fn batch_of_64_different_scenes_matches_each_scene_stepped_alone() {
    batch_matches_worlds_alone(Backend::Cpu, &scenes(64), 300, 10, true);
}

/// Eight worlds of columns and pyramids, each knocked by an impulse so they move.
fn knocked_batch() -> WorldBatch {
    knocked_on(Backend::Cpu)
}

/// [`knocked_batch`]'s worlds on `backend`.
fn knocked_on(backend: Backend) -> WorldBatch {
    let scenes: Vec<Scene> = (0..8)
        .map(|i| match i % 2 {
            0 => builders::stack(4 + i),
            _ => builders::pyramid(3),
        })
        .collect();
    let config = WorldConfig {
        backend,
        ..WorldConfig::default()
    };
    let mut batch = WorldBatch::from_scenes(&scenes, config).unwrap();
    let actions: Vec<Action> = batch
        .ids()
        .into_iter()
        .map(|id| {
            let top = *batch.handles(id).unwrap().last().unwrap();
            let p = batch
                .world(id)
                .unwrap()
                .pose(top)
                .unwrap()
                .translation
                .vector;
            Action::impulse(id, top, Vec3::new(3.0, 0.0, 1.0), Point3::from(p))
        })
        .collect();
    batch.apply_actions(&actions).unwrap();
    batch
}

fn all_bits(batch: &WorldBatch) -> Vec<Vec<u32>> {
    batch
        .ids()
        .into_iter()
        .map(|id| batch_bits(batch, id))
        .collect()
}

#[test]
fn reset_of_one_world_leaves_the_others_bitwise_untouched_and_replays_the_original() {
    let (mut reset, mut twin) = (knocked_batch(), knocked_batch());
    let ids = reset.ids();
    let k = 3;
    for _ in 0..40 {
        reset.step().unwrap();
        twin.step().unwrap();
    }
    reset.save_state(ids[k]).unwrap();
    assert_eq!(reset.reset_cost_steps(ids[k]).unwrap(), 40);
    let at_save = all_bits(&reset);
    let mut twin_after_save = Vec::new();
    for _ in 0..40 {
        reset.step().unwrap();
        twin.step().unwrap();
        twin_after_save.push(all_bits(&twin)[k].clone());
    }
    let before = all_bits(&reset);
    // World k moved between the save and now, so the reset has something to undo.
    assert_ne!(before[k], at_save[k]);
    reset.reset(&[ids[k]]).unwrap();
    let after = all_bits(&reset);
    for (j, (a, b)) in after.iter().zip(&before).enumerate() {
        if j == k {
            assert_eq!(a, &at_save[k], "world {k} is back at its saved state");
        } else {
            assert_eq!(a, b, "world {j} was not reset and must be untouched");
        }
    }
    assert_eq!(reset.step_count(ids[k]).unwrap(), 40);
    // From the saved state, world k steps exactly as it did the first time; the others keep
    // stepping exactly as the twin batch's, which was never reset.
    for (s, expected) in twin_after_save.iter().enumerate() {
        reset.step().unwrap();
        twin.step().unwrap();
        let (r, t) = (all_bits(&reset), all_bits(&twin));
        assert_eq!(&r[k], expected, "world {k}, step {s} after the reset");
        for j in (0..ids.len()).filter(|&j| j != k) {
            assert_eq!(r[j], t[j], "world {j}, step {s} after the reset");
        }
    }
    // A second reset to the same state gives the same bits again.
    reset.reset(&[ids[k]]).unwrap();
    assert_eq!(all_bits(&reset)[k], at_save[k]);
}

/// Whether `backend` has an adapter here; without one the test is skipped, which under
/// `TUMBLE_REQUIRE_GPU=1` is a failure instead.
fn gpu_available(backend: Backend) -> bool {
    let config = WorldConfig {
        backend,
        ..WorldConfig::default()
    };
    match World::new(config) {
        Ok(_) => true,
        Err(e @ Error::BackendUnavailable { .. })
            if std::env::var("TUMBLE_REQUIRE_GPU").as_deref() != Ok("1") =>
        {
            eprintln!("skipped {backend:?}: {e}");
            false
        }
        Err(e) => panic!("{backend:?}: {e}"),
    }
}

/// Three small, different scenes (one with a kinematic paddle): few bodies, so lavapipe
/// steps them quickly.
fn small_scenes() -> Vec<Scene> {
    vec![builders::stack(3), mixed(7, 3), builders::pyramid(2)]
}

/// Steps of the GPU runs: lavapipe takes tens of milliseconds per step of one world, so the
/// runs are short, with actions on about every other step. The column and the pyramid rest
/// on the floor from the first step, so contacts and warm starts reach the compared bits as
/// well as the actions.
const GPU_STEPS: usize = 21;

#[test]
fn gpu_batch_matches_each_scene_stepped_alone() {
    if gpu_available(Backend::Gpu) {
        // Twelve worlds of eight kinds, some with their own gravity or time step (so the
        // batch runs several device worlds, one per config), one device step per config.
        batch_matches_worlds_alone(Backend::Gpu, &scenes(12), GPU_STEPS, 2, false);
    }
}

#[test]
fn hybrid_batch_matches_each_scene_stepped_alone() {
    if gpu_available(Backend::Hybrid) {
        batch_matches_worlds_alone(Backend::Hybrid, &small_scenes()[..2], GPU_STEPS, 2, true);
    }
}
