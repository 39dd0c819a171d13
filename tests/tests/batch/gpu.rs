//! `WorldBatch` on `Backend::Gpu`: the worlds of one config in one device world. A reset to a
//! state saved mid-run restarts the world cold from its saved bodies, and worlds that come
//! and go leave the other worlds' bits as they would be without them.

use super::*;

#[test]
fn gpu_reset_to_a_mid_run_save_restarts_from_the_saved_bodies_and_touches_no_other_world() {
    if !gpu_available(Backend::Gpu) {
        return;
    }
    let (mut reset, mut twin) = (knocked_on(Backend::Gpu), knocked_on(Backend::Gpu));
    // One config: one device world steps all eight.
    assert_eq!(reset.device_worlds(), 1);
    let ids = reset.ids();
    let k = 3;
    for _ in 0..15 {
        reset.step().unwrap();
        twin.step().unwrap();
    }
    reset.save_state(ids[k]).unwrap();
    let at_save = all_bits(&reset);
    for _ in 0..15 {
        reset.step().unwrap();
        twin.step().unwrap();
    }
    let before = all_bits(&reset);
    assert_ne!(before[k], at_save[k], "world {k} moved after the save");
    reset.reset(&[ids[k]]).unwrap();
    let after = all_bits(&reset);
    for (j, (a, b)) in after.iter().zip(&before).enumerate() {
        if j == k {
            assert_eq!(a, &at_save[k], "world {k} is back at its saved bodies");
        } else {
            assert_eq!(a, b, "world {j} was not reset and must be untouched");
        }
    }
    assert_eq!(reset.step_count(ids[k]).unwrap(), 15);
    // The others step on exactly as the twin's, whose world k was never reset; world k
    // restarts cold, so it runs on its own (deterministic) way: a second batch reset the same
    // way gives the same bits.
    let mut again = knocked_on(Backend::Gpu);
    for _ in 0..15 {
        again.step().unwrap();
    }
    again.save_state(ids[k]).unwrap();
    for _ in 0..15 {
        again.step().unwrap();
    }
    again.reset(&[ids[k]]).unwrap();
    for s in 0..10 {
        reset.step().unwrap();
        twin.step().unwrap();
        again.step().unwrap();
        let (r, t, a) = (all_bits(&reset), all_bits(&twin), all_bits(&again));
        for j in (0..ids.len()).filter(|&j| j != k) {
            assert_eq!(r[j], t[j], "world {j}, step {s} after the reset");
        }
        assert_eq!(r[k], a[k], "world {k}, step {s} after the reset, two runs");
    }
}

#[test]
fn gpu_worlds_that_come_and_go_leave_the_others_bits_alone() {
    if !gpu_available(Backend::Gpu) {
        return;
    }
    // Two batches step alike; in one, a world is removed, a world added (into the freed slot)
    // and a body added to a third world, between steps. Every world untouched by those calls
    // keeps stepping with the twin's bits: the new upload keeps their contacts.
    let (mut changed, mut twin) = (knocked_on(Backend::Gpu), knocked_on(Backend::Gpu));
    let ids = changed.ids();
    for _ in 0..12 {
        changed.step().unwrap();
        twin.step().unwrap();
    }
    changed.remove_world(ids[2]).unwrap();
    let config = WorldConfig {
        backend: Backend::Gpu,
        ..WorldConfig::default()
    };
    let spec = WorldSpec::from_scene(&builders::stack(3), config).unwrap();
    let (new_id, _) = changed.add_world(spec).unwrap();
    assert_eq!(new_id.index(), ids[2].index(), "the freed slot is reused");
    assert!(
        changed.world(ids[2]).is_err(),
        "the removed world's id stays dead"
    );
    changed
        .add_body(
            ids[5],
            BodyDesc::dynamic()
                .cuboid(Vec3::new(0.3, 0.2, 0.4))
                .translation(0.5, 6.0, 0.2),
        )
        .unwrap();
    for s in 0..12 {
        changed.step().unwrap();
        twin.step().unwrap();
        for j in [0, 1, 3, 4, 6, 7] {
            assert_eq!(
                batch_bits(&changed, ids[j]),
                batch_bits(&twin, ids[j]),
                "world {j}, step {s} after the changes"
            );
        }
    }
    // The grown world fell further apart from its twin (a box landed on it) and the new
    // world stands where a fresh column of 3 stands after 12 steps.
    assert_ne!(
        batch_bits(&changed, ids[5])[..],
        batch_bits(&twin, ids[5])[..]
    );
    let (mut alone, _) = World::from_scene(&builders::stack(3), config).unwrap();
    for _ in 0..12 {
        alone.step().unwrap();
    }
    assert_eq!(batch_bits(&changed, new_id), world_bits(&alone));
}

#[test]
fn gpu_reset_after_a_body_was_added_restarts_cold_as_a_plain_reset_does() {
    if !gpu_available(Backend::Gpu) {
        return;
    }
    // Two batches step alike; then world k is reset in both, in the second after a body was
    // added to it (so its bodies change back in the reset and the batch is laid out again).
    // Both resets return the same bodies and must drop the world's contacts: the world then
    // steps with the same bits in both batches.
    let (mut plain, mut grown) = (knocked_on(Backend::Gpu), knocked_on(Backend::Gpu));
    let ids = plain.ids();
    let k = 2;
    for _ in 0..15 {
        plain.step().unwrap();
        grown.step().unwrap();
    }
    grown
        .add_body(ids[k], BodyDesc::dynamic().translation(0.0, 8.0, 0.0))
        .unwrap();
    plain.reset(&[ids[k]]).unwrap();
    grown.reset(&[ids[k]]).unwrap();
    for s in 0..10 {
        plain.step().unwrap();
        grown.step().unwrap();
        assert_eq!(
            batch_bits(&plain, ids[k]),
            batch_bits(&grown, ids[k]),
            "world {k}, step {s} after the reset"
        );
    }
}

#[test]
fn a_gpu_batch_whose_worlds_all_emptied_steps_again_once_bodies_come_back() {
    if !gpu_available(Backend::Gpu) {
        return;
    }
    let config = WorldConfig {
        backend: Backend::Gpu,
        ..WorldConfig::default()
    };
    let full = WorldSpec::from_scene(&builders::stack(2), config).unwrap();
    let mut batch =
        WorldBatch::from_specs(Backend::Gpu, vec![full, WorldSpec::new(config)]).unwrap();
    let ids = batch.ids();
    batch.step().unwrap();
    // No body left in the batch's only device world, then a falling box in the empty world.
    batch.remove_world(ids[0]).unwrap();
    batch.step().unwrap();
    let cube = batch
        .add_body(ids[1], BodyDesc::dynamic().translation(0.0, 5.0, 0.0))
        .unwrap();
    for _ in 0..30 {
        batch.step().unwrap();
    }
    // Half a second of free fall from 5 m: about 1.2 m down (the exact figure is the
    // integrator's; nothing here touches the box).
    let y = batch
        .world(ids[1])
        .unwrap()
        .pose(cube)
        .unwrap()
        .translation
        .y;
    assert!((3.5..4.0).contains(&y), "the box is at y = {y}");
}
