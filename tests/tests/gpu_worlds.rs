//! Several independent worlds in one `GpuWorld` (`set_bodies_in_worlds`): one set of buffers,
//! one set of dispatches per step, and each world's bodies end bitwise equal to the same
//! world's bodies stepped alone. Every world stands at the same place, so a pair formed across
//! worlds, a sweep that ran past its world or a constraint colored by another world's
//! numbering would change a bit somewhere.
//!
//! Needs a GPU (or lavapipe): without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.

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

#[test]
fn worlds_stepped_as_one_batch_end_bitwise_equal_to_each_stepped_alone() {
    // Twelve worlds, 200 steps (3.3 s): landings, slides into the wall, piles settling; the
    // bodies (under 1,024) and pairs take the single-workgroup sorts, and the solve one
    // fused workgroup per world (SolvePath::Worlds; a batch this small is not packed into
    // groups), where each world alone takes the single-workgroup fused path.
    batch_matches_alone(12, 200, GpuWorldConfig::default());
}

#[test]
fn groups_of_worlds_with_and_without_contacts_end_bitwise_equal_to_each_stepped_alone() {
    // The solve runs consecutive worlds as one group per workgroup (up to 64 bodies), over
    // the union of their manifold ranges. Every third world here never touches anything (a
    // cube falling from 100 m, 4.9 m in these 60 steps), so groups begin, hold and end with
    // worlds that have no manifold range (their entries stay 0, 0): a group range taken from
    // such an entry would reach into other groups' constraints and change their bits.
    let material = Material {
        friction: 0.6,
        restitution: 0.0,
    };
    let scenes: Vec<_> = (0..24u64)
        .map(|w| {
            if w % 3 == 1 {
                let cube = Body::new(
                    BodyKind::Dynamic,
                    Cuboid::new(Vec3::repeat(0.5)),
                    Pose::translation(0.0, 100.0, 0.0),
                    1.0,
                    material,
                )
                .unwrap();
                (vec![floor(material), cube], vec![BodyState::default(); 2])
            } else {
                small_world(w)
            }
        })
        .collect();
    let packed = GpuWorldConfig {
        world_grouping: WorldGrouping::Packed,
        ..GpuWorldConfig::default()
    };
    scenes_match_alone(&scenes, 60, packed);
    let shared = GpuWorldConfig {
        fused_memory: FusedMemory::Workgroup,
        ..packed
    };
    scenes_match_alone(&scenes, 60, shared);
}

#[test]
fn a_batch_is_packed_into_groups_of_worlds_only_when_asked_or_large() {
    // The grouping never changes a bit (the test above), so what it must get right is which
    // workgroups run: a small batch one world per workgroup (it would leave most of a GPU
    // idle packed), a large one or one asked for packed as few workgroups as fit 64 bodies.
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let groups = |count: usize, grouping| {
        let scenes: Vec<_> = (0..count as u64).map(|w| small_world(w % 4)).collect();
        let (bodies, states, worlds, firsts) = concat(&scenes);
        let config = GpuWorldConfig {
            world_grouping: grouping,
            ..GpuWorldConfig::default()
        };
        let mut world = GpuWorld::new(&ctx, config).unwrap();
        world
            .set_bodies_in_worlds(&bodies, &states, &worlds)
            .unwrap();
        (world.solver().world_group_count(), bodies.len(), firsts)
    };
    let (alone, _, _) = groups(24, WorldGrouping::Alone);
    assert_eq!(alone, 24, "one group per world when alone");
    let (auto, bodies, _) = groups(24, WorldGrouping::Auto);
    assert!((bodies as u32) < WORLDS_PACK_MIN_BODIES);
    assert_eq!(
        auto, 24,
        "a batch of {bodies} bodies is small: one world per group"
    );
    let (packed, bodies, firsts) = groups(24, WorldGrouping::Packed);
    let mut starts: Vec<u32> = firsts.iter().map(|&f| f as u32).collect();
    starts.push(bodies as u32);
    assert_eq!(
        packed as usize,
        world_groups(&starts, WORLD_GROUP_BODIES).len()
    );
    assert!(
        packed < 24,
        "{packed} groups: the small worlds were not packed"
    );
    // Enough worlds for WORLDS_PACK_MIN_BODIES: Auto packs them as Packed does.
    let count = 24 * (WORLDS_PACK_MIN_BODIES as usize / bodies + 1);
    let (auto, bodies, _) = groups(count, WorldGrouping::Auto);
    assert!(bodies as u32 >= WORLDS_PACK_MIN_BODIES);
    let (packed, _, _) = groups(count, WorldGrouping::Packed);
    assert_eq!(auto, packed);
    assert!((auto as usize) < count, "{auto} groups for {count} worlds");
}
#[test]
fn worlds_with_their_bodies_in_workgroup_memory_end_bitwise_equal_to_each_stepped_alone() {
    // solve_worlds_shared (each world's bodies in workgroup memory, workgroup barriers only),
    // which GPUs take and lavapipe only when asked: a barrier too weak or a body slot off by
    // the world's first body would change a bit in these 120 steps.
    let config = GpuWorldConfig {
        fused_memory: FusedMemory::Workgroup,
        ..GpuWorldConfig::default()
    };
    batch_matches_alone(12, 120, config);
}

#[test]
fn worlds_on_the_wide_solver_path_end_bitwise_equal_to_each_stepped_alone() {
    // The batch on the wide path (one dispatch per color and pass for all worlds), as large
    // worlds take it: the coloring numbers each world's constraints from its first.
    let config = GpuWorldConfig {
        path: PathPolicy::Always(SolvePath::Wide),
        ..GpuWorldConfig::default()
    };
    batch_matches_alone(12, 120, config);
}

#[test]
fn a_batch_of_130_worlds_matches_on_the_radix_sort_and_without_long_box_lists() {
    // 130 worlds: more than 1,024 bodies and pair slots (the pair sort is the radix sort
    // rather than the single-workgroup one; the bodies sort one workgroup per world,
    // sort_world_bodies, where each world alone takes rank_sort), more floors than the
    // long-box list holds (64, so every floor is swept with its world's boxes) and 8 bits of
    // world index in the sort keys.
    batch_matches_alone(130, 60, GpuWorldConfig::default());
}

#[test]
fn a_batch_with_a_world_of_over_1024_bodies_sorts_all_bodies_at_once_and_matches() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // A world of 1,157 bodies (a floor and a 34 x 34 grid of cubes dropped from 2 to 6 cm)
    // beside a small world: the sort by world takes worlds of at most 1,024 bodies, so this
    // batch's bodies go through the radix sort of the whole list, with the world leading the
    // keys. Each world must still end with the bits it gets alone.
    let material = Material {
        friction: 0.6,
        restitution: 0.0,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    let mut bodies = vec![floor(material)];
    for i in 0..34 * 34 {
        let (x, z) = ((i % 34) as Real * 1.1 - 18.0, (i / 34) as Real * 1.1 - 18.0);
        let y = 0.5 + rng.random_range(0.02..0.06);
        bodies.push(
            Body::new(
                BodyKind::Dynamic,
                Cuboid::new(Vec3::repeat(0.5)),
                Pose::new(Vec3::new(x, y, z), Vec3::zeros()),
                1.0,
                material,
            )
            .unwrap(),
        );
    }
    let states = vec![BodyState::default(); bodies.len()];
    let scenes = [(bodies, states), small_world(2)];
    let (bodies, states, worlds, firsts) = concat(&scenes);
    let steps = 20;
    let batch = run_on(
        &ctx,
        GpuWorldConfig::default(),
        &bodies,
        &states,
        &worlds,
        steps,
    );
    for (w, (b, s)) in scenes.iter().enumerate() {
        let alone = run(&ctx, b, s, &[], steps);
        for (i, pose) in alone.iter().enumerate() {
            assert_eq!(
                pose_bits(pose),
                pose_bits(&batch[firsts[w] + i]),
                "world {w}, body {i}"
            );
        }
    }
    // The grid landed: every cube of the large world ends resting on the floor (centre
    // within 1 cm of 0.5 m), which it reaches only through its own floor contacts.
    let grid = &batch[1..scenes[0].0.len()];
    assert!(
        grid.iter().all(|p| (p.position[1] - 0.5).abs() < 0.01),
        "a cube of the large world is not resting on its floor"
    );
}

#[test]
fn bad_world_numbering_is_refused_and_names_the_entry() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let (bodies, states) = small_world(1);
    let mut world = GpuWorld::new(&ctx, GpuWorldConfig::default()).unwrap();
    let n = bodies.len();
    // A gap in the numbering, a world out of order, and a list of the wrong length.
    let mut gap = vec![0; n];
    gap[n - 1] = 2;
    let err = world
        .set_bodies_in_worlds(&bodies, &states, &gap)
        .unwrap_err();
    assert!(
        err.to_string().contains(&format!("worlds[{}]", n - 1)),
        "{err}"
    );
    let mut back = vec![1; n];
    back[0] = 0;
    back[n - 1] = 0;
    let err = world
        .set_bodies_in_worlds(&bodies, &states, &back)
        .unwrap_err();
    assert!(
        err.to_string().contains(&format!("worlds[{}]", n - 1)),
        "{err}"
    );
    let err = world
        .set_bodies_in_worlds(&bodies, &states, &[0])
        .unwrap_err();
    assert!(err.to_string().contains("worlds.len()"), "{err}");
    assert_eq!(
        world.body_count(),
        0,
        "a refused upload leaves the world empty"
    );
}

#[test]
fn a_forgotten_world_restarts_as_if_new_and_the_others_keep_their_history() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // Six worlds step 120 steps; then world 2 and world 5 are put back to their start (poses
    // and velocities written, their pairs forgotten) and all step 60 more. The reset worlds
    // must end as the same worlds run 60 steps from new, the others as run 180 steps alone:
    // a pair carried into a reset world (its impulses, hysteresis or color seed) or a pair
    // dropped from a kept one would change a bit.
    let scenes: Vec<_> = (0..6).map(small_world).collect();
    let (bodies, states, worlds, firsts) = concat(&scenes);
    let mut batch = GpuWorld::new(&ctx, GpuWorldConfig::default()).unwrap();
    batch
        .set_bodies_in_worlds(&bodies, &states, &worlds)
        .unwrap();
    for _ in 0..120 {
        batch.step().unwrap();
    }
    let reset = [2u32, 5];
    for &w in &reset {
        let (b, s) = &scenes[w as usize];
        for (i, (body, state)) in b.iter().zip(s).enumerate() {
            let g = firsts[w as usize] + i;
            batch.set_pose(g, &body.pose).unwrap();
            batch
                .set_velocity(g, &state.linear_velocity, &state.angular_velocity)
                .unwrap();
        }
    }
    batch.forget_worlds(&reset).unwrap();
    for _ in 0..60 {
        batch.step().unwrap();
    }
    let after = batch.read_now(ReadRequest::MOTION).unwrap().poses;
    for (w, (b, s)) in scenes.iter().enumerate() {
        let steps = if reset.contains(&(w as u32)) { 60 } else { 180 };
        let alone = run(&ctx, b, s, &[], steps);
        for (i, pose) in alone.iter().enumerate() {
            let fused = &after[firsts[w] + i];
            assert_eq!(
                pose_bits(pose),
                pose_bits(fused),
                "world {w} ({steps} steps), body {i}: alone {pose:?}, in the batch {fused:?}"
            );
        }
    }
    assert!(
        batch.forget_worlds(&[6]).is_err(),
        "a world index past the last is refused"
    );
}

#[test]
fn worlds_whose_bodies_did_not_change_keep_their_history_through_a_new_upload() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    use tumble_gpu::kernels::remap_pairs::REMAP_DROPPED;
    // Five worlds step 100 steps. Then the batch is uploaded again: world 1 leaves, world 3
    // gets a new box, and a new world comes in front. Worlds 0, 2 and 4 keep their pairs
    // (renumbered) and must end as run 160 steps alone; world 3 restarts from its state at
    // step 100 with the new box, as a world alone does when a body is added (it uploads
    // again); the new world as run 60 steps alone.
    let scenes: Vec<_> = (0..5).map(small_world).collect();
    let (bodies, states, worlds, firsts) = concat(&scenes);
    let mut batch = GpuWorld::new(&ctx, GpuWorldConfig::default()).unwrap();
    batch
        .set_bodies_in_worlds(&bodies, &states, &worlds)
        .unwrap();
    for _ in 0..100 {
        batch.step().unwrap();
    }
    let now = batch.read_now(ReadRequest::MOTION).unwrap();
    let state_of = |w: usize| -> (Vec<Body>, Vec<BodyState>) {
        let (b, _) = &scenes[w];
        let bodies = (0..b.len())
            .map(|i| {
                let mut body = b[i];
                body.pose = now.pose(firsts[w] + i);
                body
            })
            .collect();
        let states = (0..b.len()).map(|i| now.state(firsts[w] + i)).collect();
        (bodies, states)
    };
    // World 3 as it is now, plus a box dropped on it.
    let (mut w3_bodies, mut w3_states) = state_of(3);
    w3_bodies.push(
        Body::new(
            BodyKind::Dynamic,
            Cuboid::new(Vec3::new(0.3, 0.2, 0.4)),
            Pose::translation(0.5, 4.0, 0.2),
            1.0,
            Material {
                friction: 0.6,
                restitution: 0.0,
            },
        )
        .unwrap(),
    );
    w3_states.push(BodyState::default());
    let (new_bodies, new_states) = small_world(17);
    // The new layout: the new world, then worlds 0, 2, 3 (grown) and 4.
    let order: [(Vec<Body>, Vec<BodyState>); 5] = [
        (new_bodies.clone(), new_states.clone()),
        state_of(0),
        state_of(2),
        (w3_bodies.clone(), w3_states.clone()),
        state_of(4),
    ];
    let (bodies2, states2, worlds2, firsts2) = concat(&order);
    // Old world -> new position when kept; world 1 (gone) drops to where world 2 now
    // starts, world 3 (changed) to its own new start.
    let mut remap = vec![0u32; bodies.len()];
    for (w, (b, _)) in scenes.iter().enumerate() {
        for i in 0..b.len() {
            remap[firsts[w] + i] = match w {
                0 => (firsts2[1] + i) as u32,
                1 => REMAP_DROPPED | firsts2[2] as u32,
                2 => (firsts2[2] + i) as u32,
                3 => REMAP_DROPPED | firsts2[3] as u32,
                _ => (firsts2[4] + i) as u32,
            };
        }
    }
    let kept = batch
        .set_bodies_in_worlds_keeping(&bodies2, &states2, &worlds2, &remap)
        .unwrap();
    assert!(kept, "the pair buffers did not need to grow");
    for _ in 0..60 {
        batch.step().unwrap();
    }
    let after = batch.read_now(ReadRequest::MOTION).unwrap().poses;
    let check = |what: &str, alone: Vec<GpuPose>, first: usize| {
        for (i, pose) in alone.iter().enumerate() {
            let fused = &after[first + i];
            assert_eq!(
                pose_bits(pose),
                pose_bits(fused),
                "{what}, body {i}: alone {pose:?}, in the batch {fused:?}"
            );
        }
    };
    for (w, new) in [(0, 1), (2, 2), (4, 4)] {
        let (b, s) = &scenes[w];
        check(
            &format!("kept world {w}"),
            run(&ctx, b, s, &[], 160),
            firsts2[new],
        );
    }
    check(
        "world 3 with a box added",
        run(&ctx, &w3_bodies, &w3_states, &[], 60),
        firsts2[3],
    );
    check(
        "the new world",
        run(&ctx, &new_bodies, &new_states, &[], 60),
        firsts2[0],
    );
}
