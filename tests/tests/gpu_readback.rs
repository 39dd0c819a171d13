//! `Backend::Gpu` reads back only what the caller reads, and reading changes nothing else.
//!
//! A GPU step is submitted without waiting; getters read its results lazily, from a staging
//! copy recorded with the step when the caller read that part after the previous step
//! (`ReadbackOverrides`' `Auto`), or from the GPU buffers otherwise. These tests check that
//! (a) the bytes crossing the bus are exactly those of the parts read, and (b) how and when
//! the caller reads, and whether copies are forced on or off, never changes a result: the
//! same calls give bitwise equal poses, velocities and contacts under every policy.
//!
//! Needs a GPU (or lavapipe): without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.

use tumble::prelude::*;
use tumble::{EffectOverrides, EffectSwitch, ReadbackOverrides};
use tumble_gpu::GpuContext;
use tumble_gpu::layout::{GpuPose, GpuVelocity};
use tumble_tests::facade::{add_floor, cube_at};

/// Steps per run: 1.5 s at 60 Hz, enough for the dropped cube to land on the stacks and the
/// user's pokes to play out.
const STEPS: usize = 90;

fn have_gpu() -> bool {
    GpuContext::for_tests().is_some()
}

/// A world on the GPU backend with `effects`, the rest default.
fn gpu_world(effects: EffectOverrides) -> World {
    let config = WorldConfig {
        backend: Backend::Gpu,
        effects,
        ..Default::default()
    };
    World::new(config).expect("GPU world")
}

fn world(readback: ReadbackOverrides) -> (World, Vec<BodyHandle>) {
    world_with(EffectOverrides {
        readback,
        ..Default::default()
    })
}

/// [`world`] with `effects`.
fn world_with(effects: EffectOverrides) -> (World, Vec<BodyHandle>) {
    let mut world = gpu_world(effects);
    let mut handles = vec![add_floor(&mut world, 10.0)];
    for (x, z) in [(-1.5, 0.0), (0.0, 0.0), (1.5, 0.0)] {
        for level in 0..3 {
            let cube = BodyDesc::dynamic().translation(x, 0.5 + level as Real, z);
            handles.push(world.add_body(cube).unwrap());
        }
    }
    let dropped = BodyDesc::dynamic()
        .cuboid(Vec3::new(0.3, 0.3, 0.3))
        .translation(0.1, 5.0, 0.2)
        .angular_velocity(Vec3::new(1.0, 2.0, 0.5));
    handles.push(world.add_body(dropped).unwrap());
    (world, handles)
}

/// Everything a caller can observe of a world, as bits: the bodies of `handles`, then every
/// contact.
fn observe(world: &World, handles: &[BodyHandle]) -> (Vec<u32>, Vec<u32>) {
    let mut bits = Vec::new();
    for &h in handles {
        let p = world.pose(h).unwrap();
        bits.extend(p.translation.vector.iter().map(|c| c.to_bits()));
        bits.extend(p.rotation.coords.iter().map(|c| c.to_bits()));
        bits.extend(
            world
                .linear_velocity(h)
                .unwrap()
                .iter()
                .map(|c| c.to_bits()),
        );
        bits.extend(
            world
                .angular_velocity(h)
                .unwrap()
                .iter()
                .map(|c| c.to_bits()),
        );
    }
    let bodies = std::mem::take(&mut bits);
    for c in world.contacts() {
        bits.extend(c.normal.iter().map(|x| x.to_bits()));
        for p in &c.points {
            bits.extend(p.position.coords.iter().map(|x| x.to_bits()));
            bits.push(p.depth.to_bits());
            bits.push(p.normal_impulse.to_bits());
            bits.push(p.id);
        }
    }
    (bodies, bits)
}

/// Runs the scripted calls; `read_every` says after which steps the caller reads a pose, and
/// `poke` whether the user's changes are made.
fn run(readback: ReadbackOverrides, read_every: usize, poke: bool) -> (Vec<u32>, Vec<u32>) {
    let (mut world, handles) = world(readback);
    let top = handles[3];
    for step in 0..STEPS {
        world.step().unwrap();
        if read_every > 0 && step % read_every == 0 {
            world.pose(handles[1]).unwrap();
        }
        if step == 60 {
            // Renumbers the bodies: a full upload from the host arrays.
            cube_at(&mut world, 3.0, 0.5, 0.0);
        }
        // The user's changes, each of which needs the current state on the host first.
        if !poke {
            continue;
        }
        match step {
            20 => world
                .apply_impulse(top, Vec3::new(0.5, 0.0, 0.0), Point3::new(-1.5, 2.9, 0.1))
                .unwrap(),
            35 => world
                .set_linear_velocity(handles[6], Vec3::new(0.0, 2.0, 0.0))
                .unwrap(),
            50 => {
                let mut pose = world.pose(handles[9]).unwrap();
                pose.translation.vector.y += 0.5;
                world.set_pose(handles[9], pose).unwrap();
            }
            _ => {}
        }
    }
    observe(&world, &handles)
}

#[test]
fn how_the_caller_reads_never_changes_a_result() {
    if !have_gpu() {
        return;
    }
    let off = ReadbackOverrides {
        poses: EffectSwitch::Off,
        velocities: EffectSwitch::Off,
        contacts: EffectSwitch::Off,
        sleeping: EffectSwitch::Off,
        stats: EffectSwitch::Off,
    };
    // Reads copied with every step, read rarely, never copied with the step: the GPU step is
    // deterministic, so any difference would be a stale host value uploaded back, a lost
    // user change, or a copy read from the wrong step. Hence bitwise.
    let reference = run(ReadbackOverrides::ALL_ON, 1, true);
    assert_eq!(
        run(ReadbackOverrides::default(), 7, true),
        reference,
        "Auto, sparse reads"
    );
    assert_eq!(
        run(ReadbackOverrides::default(), 0, true),
        reference,
        "Auto, no reads"
    );
    assert_eq!(run(off, 3, true), reference, "never copied with the step");
    // And the changes reached the GPU: without them the original bodies end elsewhere.
    let untouched = run(ReadbackOverrides::ALL_ON, 1, false);
    assert_ne!(untouched.0, reference.0, "the user's changes had an effect");
}

#[test]
fn a_step_copies_only_what_the_caller_read() {
    if !have_gpu() {
        return;
    }
    let (mut world, handles) = world(ReadbackOverrides::default());
    let n = handles.len() as u64;
    let pose_bytes = n * std::mem::size_of::<GpuPose>() as u64;
    let velocity_bytes = n * std::mem::size_of::<GpuVelocity>() as u64;

    // A caller that reads nothing moves nothing across the bus.
    for _ in 0..10 {
        world.step().unwrap();
    }
    assert_eq!(world.readback_bytes(), 0, "nothing was read");

    // Reading one pose per step brings every pose (one array) and nothing else: the first
    // read is a direct read, the following ones come with their steps.
    let mut before = world.readback_bytes();
    for step in 0..5 {
        world.step().unwrap();
        let p = world.pose(handles[2]).unwrap();
        assert!(p.translation.y.is_finite());
        let after = world.readback_bytes();
        assert_eq!(after - before, pose_bytes, "step {step}: poses only");
        before = after;
    }

    // Velocities too, from the next step on, with the poses.
    world.step().unwrap();
    world.pose(handles[2]).unwrap();
    world.linear_velocity(handles[2]).unwrap();
    before = world.readback_bytes();
    world.step().unwrap();
    world.pose(handles[2]).unwrap();
    world.angular_velocity(handles[2]).unwrap();
    assert_eq!(
        world.readback_bytes() - before,
        pose_bytes + velocity_bytes,
        "poses and velocities, copied with the step"
    );

    // Contacts are copied only after the caller looked at them; the stacks rest on the
    // floor, so there are manifolds to copy.
    before = world.readback_bytes();
    world.step().unwrap();
    let pairs = world.contact_pairs();
    assert!(pairs.len() >= 9, "9 resting cubes touch: {}", pairs.len());
    assert!(
        world.readback_bytes() - before > 0,
        "the contacts crossed the bus"
    );

    // A caller that stops reading stops paying after the one step that still expected it.
    world.step().unwrap();
    before = world.readback_bytes();
    for _ in 0..5 {
        world.step().unwrap();
    }
    assert_eq!(
        world.readback_bytes(),
        before,
        "nothing read, nothing copied"
    );
}

#[test]
fn changes_are_made_to_the_current_state() {
    if !have_gpu() {
        return;
    }
    let (mut world, handles) = world(ReadbackOverrides::default());
    for _ in 0..30 {
        world.step().unwrap();
    }
    // The dropped cube is in the air: an impulse adds j/m to the velocity the GPU computed,
    // exactly as the CPU backend's apply_impulse does.
    let cube = handles[handles.len() - 1];
    let v = world.linear_velocity(cube).unwrap();
    let m = world.mass(cube).unwrap();
    let j = Vec3::new(0.2, 0.0, 0.0);
    let centre = world.pose(cube).unwrap().translation.vector;
    world.apply_impulse(cube, j, Point3::from(centre)).unwrap();
    let after = world.linear_velocity(cube).unwrap();
    // f32 round-off of one add: a few ulps of the 4 m/s fall speed.
    assert!(
        (after - (v + j / m)).norm() < 1e-5,
        "{after:?} != {v:?} + {:?}",
        j / m
    );
    // A pose set is the pose reported, and the pose the next step starts from.
    let target = Pose::translation(4.0, 3.0, 0.0);
    world.set_pose(cube, target).unwrap();
    assert_eq!(world.pose(cube).unwrap(), target);
    world.step().unwrap();
    let moved = world.pose(cube).unwrap().translation.vector;
    // One step of free fall from rest-height 3 m with the kept velocity: within 0.2 m.
    assert!(
        (moved - target.translation.vector).norm() < 0.2,
        "the step started from the set pose: {moved:?}"
    );
}

#[test]
fn sleep_on_the_gpu_is_read_through_the_facade() {
    if !have_gpu() {
        return;
    }
    let mut world = gpu_world(EffectOverrides {
        sleep: EffectSwitch::On,
        ..Default::default()
    });
    add_floor(&mut world, 10.0);
    let mut stacks = Vec::new();
    for x in [-2.0, 2.0] {
        let stack: Vec<BodyHandle> = (0..2)
            .map(|level| {
                let cube = BodyDesc::dynamic().translation(x, 0.5 + level as Real, 0.0);
                world.add_body(cube).unwrap()
            })
            .collect();
        stacks.push(stack);
    }
    // Resting stacks settle in a fraction of a second and sleep TIME_TO_SLEEP (0.5 s) later:
    // 2 s is ample, and a body still awake then is not coming to rest.
    let mut steps = 0;
    while world.sleeping_count() < 4 && steps < 120 {
        world.step().unwrap();
        steps += 1;
    }
    assert_eq!(
        world.sleeping_count(),
        4,
        "all four cubes asleep after {steps} steps"
    );
    let resting = world.pose(stacks[1][1]).unwrap();
    // Waking one cube wakes its stack only; the other stays asleep and does not move a bit.
    world.wake_up(stacks[0][1]).unwrap();
    world.step().unwrap();
    for &h in &stacks[0] {
        assert!(!world.is_sleeping(h).unwrap(), "the woken stack is awake");
    }
    for &h in &stacks[1] {
        assert!(world.is_sleeping(h).unwrap(), "the other stack sleeps on");
    }
    assert_eq!(world.pose(stacks[1][1]).unwrap(), resting);
}

#[test]
fn stats_read_every_step_cost_thirty_two_bytes_and_count_what_the_manifolds_hold() {
    if !have_gpu() {
        return;
    }
    // Sleep off: a sleeping island's pairs are not collided, and the counts would be 0.
    let (mut world, _) = world_with(EffectOverrides::NO_SLEEP);
    // The stacks settle onto the floor and each other: resting manifolds with overlap.
    for _ in 0..30 {
        world.step().unwrap();
    }
    let mut before = world.readback_bytes();
    for step in 0..5 {
        world.step().unwrap();
        let stats = *world.stats();
        // The counts alone cross the bus: the first read directly, the next ones copied
        // with their steps (the GPU reduces every manifold to eight words).
        let after = world.readback_bytes();
        assert_eq!(after - before, 32, "step {step}: the counts only");
        before = after;
        // Three stacks of three cubes on the floor: 9 resting manifolds at least.
        assert!(stats.manifolds >= 9, "step {step}: {stats:?}");
    }
    // The same numbers as counted from the manifolds themselves (read after the counts, so
    // the counts above came from the GPU's summary).
    world.step().unwrap();
    let stats = *world.stats();
    let reports = world.contacts();
    assert_eq!(stats.manifolds, reports.len());
    assert_eq!(
        stats.contact_points,
        reports.iter().map(|r| r.points.len()).sum::<usize>()
    );
    let deepest = reports.iter().map(|r| r.max_depth()).fold(0.0, Real::max);
    assert_eq!(stats.max_penetration.to_bits(), deepest.to_bits());
    // Soft contacts rest with a small overlap: the deepest is positive and well under a
    // centimetre, or the comparison above would be of two zeros.
    assert!(
        stats.max_penetration > 0.0 && stats.max_penetration < 0.01,
        "{stats:?}"
    );
    assert!(stats.pairs >= stats.manifolds, "{stats:?}");
    // The stacks rest: their pairs keep last step's manifolds (contact recycling, on by
    // default), and the summary counts them.
    assert!(
        stats.recycled_manifolds > 0 && stats.recycled_manifolds <= stats.manifolds,
        "{stats:?}"
    );

    // A caller that has the contacts copied with every step (and not the summary) gets the
    // counts from that copy: reading the stats moves no further byte.
    let (mut world, _) = world_with(EffectOverrides {
        readback: ReadbackOverrides {
            contacts: EffectSwitch::On,
            stats: EffectSwitch::Off,
            ..Default::default()
        },
        ..EffectOverrides::NO_SLEEP
    });
    for _ in 0..30 {
        world.step().unwrap();
    }
    world.step().unwrap();
    let before = world.readback_bytes();
    let copied = *world.stats();
    assert_eq!(
        world.readback_bytes(),
        before,
        "the counts came from the copy"
    );
    assert!(copied.manifolds >= 9, "the resting stacks: {copied:?}");
}

#[test]
fn the_gpu_contact_summary_matches_its_cpu_twin_copied_with_the_step_and_read_directly() {
    use tumble_geometry::Rot;
    use tumble_gpu::kernels::contact_summary::contact_summary_cpu;
    use tumble_gpu::step::{GpuWorld, GpuWorldConfig, ReadRequest};
    use tumble_solver::{BodyKind, BodyState, Material};
    use tumble_tests::gpu_solver_util::{cube, floor};
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // A 6 x 6 layer of tilted cubes pressed into the floor and into each other by different
    // amounts (0 to 5 cm): many manifolds of 1 to 4 points, each with its own deepest point,
    // so a wrong sum, a lost maximum or a manifold counted twice shows.
    let mut bodies = vec![floor(Material::default())];
    for i in 0..36 {
        let (x, z) = ((i % 6) as Real, (i / 6) as Real);
        let sink = 0.01 * (i % 6) as Real;
        let mut body = cube(BodyKind::Dynamic, Vec3::new(0.97 * x, 0.5 - sink, 0.97 * z));
        body.pose.rotation = Rot::from_euler_angles(0.02 * (i % 5) as Real, 0.3, 0.0);
        bodies.push(body);
    }
    let states = vec![BodyState::default(); bodies.len()];
    let mut world = GpuWorld::new(&ctx, GpuWorldConfig::default()).unwrap();
    world.set_bodies(&bodies, &states).unwrap();
    let both = ReadRequest {
        contacts: true,
        summary: true,
        ..Default::default()
    };
    world.request_reads(both);
    for step in 0..3 {
        world.step().unwrap();
        let copied = world
            .wait_snapshot()
            .unwrap()
            .expect("requested with the step");
        let direct = world.read_now(both).unwrap();
        for (how, snapshot) in [("copied", &copied), ("direct", &direct)] {
            let contacts = snapshot.contacts.as_ref().expect("contacts requested");
            let cpu =
                contact_summary_cpu(contacts.work.count, &contacts.manifolds, &contacts.points);
            let gpu = snapshot.summary.expect("summary requested");
            assert_eq!(gpu.manifolds, cpu.manifolds, "{how}, step {step}");
            assert_eq!(gpu.points, cpu.points, "{how}, step {step}");
            assert_eq!(gpu.pairs, cpu.pairs, "{how}, step {step}");
            assert_eq!(
                gpu.max_depth.to_bits(),
                cpu.max_depth.to_bits(),
                "{how}, step {step}: {} against {}",
                gpu.max_depth,
                cpu.max_depth
            );
            // The pressed layer: every cube touches the floor, and the deepest overlap is
            // between the 5 cm the deepest cubes were pressed into the floor (less what a
            // step pushed out) and the 28 cm a cube turned by 0.3 rad reaches into its
            // neighbour 0.97 m away.
            assert!(gpu.manifolds >= 36, "{how}, step {step}: {gpu:?}");
            assert!(
                gpu.max_depth > 0.03 && gpu.max_depth < 0.28,
                "{how}, step {step}: {gpu:?}"
            );
        }
    }
}
