//! The batch's world table through uploads: bad numbering refused by name, a forgotten world
//! restarted as new, unchanged worlds keeping their contact history through a new upload.

use super::*;

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
