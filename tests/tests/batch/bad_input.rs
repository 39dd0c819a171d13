//! Bad input to a batch: actions, reads and worlds that are refused whole, with an error
//! naming the index and the field, leaving every world bitwise as it was.

use super::*;

/// The action error's index and field, or a panic naming what came instead.
fn action_error(e: Error) -> (usize, &'static str) {
    match e {
        Error::Batch(BatchError::Action { index, field, .. }) => (index, field),
        other => panic!("expected an action error, got {other}"),
    }
}

#[test]
fn bad_actions_are_rejected_whole_and_change_nothing() {
    let mut batch = knocked_batch();
    let (other, _) = batch
        .add_world(WorldSpec::new(WorldConfig::default()).body(BodyDesc::dynamic()))
        .unwrap();
    let ids = batch.ids();
    let (a, b) = (ids[0], ids[1]);
    let floor_a = batch.handles(a).unwrap()[0];
    let cube_a = batch.handles(a).unwrap()[1];
    let removed = batch.handles(b).unwrap()[3];
    batch.remove_body(b, removed).unwrap();
    batch.remove_world(other).unwrap();
    let mut twin = knocked_batch();
    let (other_twin, _) = twin
        .add_world(WorldSpec::new(WorldConfig::default()).body(BodyDesc::dynamic()))
        .unwrap();
    twin.remove_body(b, removed).unwrap();
    twin.remove_world(other_twin).unwrap();

    let at_cube = Point3::from(
        batch
            .world(a)
            .unwrap()
            .pose(cube_a)
            .unwrap()
            .translation
            .vector,
    );
    let never_issued = handle_beyond(&batch, b);
    // A good entry, put first in every bad array: it must not be applied either.
    let good = Action::set_velocity(a, cube_a, Vec3::new(1.0, 0.0, 0.0), Vec3::zeros());
    let fast = Vec3::new(0.0, 0.0, 300.0);
    let cases: Vec<(Action, usize, &str)> = vec![
        // The removed world's id.
        (
            Action::set_velocity(other, cube_a, Vec3::zeros(), Vec3::zeros()),
            1,
            "world",
        ),
        // A removed body.
        (
            Action::set_velocity(b, removed, Vec3::zeros(), Vec3::zeros()),
            1,
            "body",
        ),
        // A handle world b never issued.
        (
            Action::set_velocity(b, never_issued, Vec3::zeros(), Vec3::zeros()),
            1,
            "body",
        ),
        (
            Action::impulse(a, cube_a, Vec3::new(Real::NAN, 0.0, 0.0), at_cube),
            1,
            "impulse",
        ),
        (
            Action::impulse(a, cube_a, Vec3::x(), Point3::new(1e6, 0.0, 0.0)),
            1,
            "point",
        ),
        (
            Action::set_velocity(a, cube_a, Vec3::new(500.0, 0.0, 0.0), Vec3::zeros()),
            1,
            "linear_velocity",
        ),
        (
            Action::set_velocity(
                a,
                cube_a,
                Vec3::zeros(),
                Vec3::new(0.0, Real::INFINITY, 0.0),
            ),
            1,
            "angular_velocity",
        ),
        (
            Action::set_velocity(a, floor_a, Vec3::x(), Vec3::zeros()),
            1,
            "linear_velocity",
        ),
        (
            Action::kinematic_target(a, cube_a, Pose::identity()),
            1,
            "kind",
        ),
    ];
    for (bad, index, field) in cases {
        let before = all_bits(&batch);
        let e = batch.apply_actions(&[good, bad]).unwrap_err();
        assert_eq!(action_error(e.clone()), (index, field), "{e}");
        assert!(
            e.to_string().contains(&format!("actions[{index}].{field}")),
            "{e}"
        );
        assert_eq!(all_bits(&batch), before, "{e}: the batch changed");
    }
    // Each impulse alone is within bounds (the cube is 1 kg: 300 m/s), the two together
    // would leave it at 600 m/s, over MAX_SPEED: the second entry is refused, from the
    // velocity the first leaves, and neither is applied.
    let pair = [
        Action::impulse(a, cube_a, fast, at_cube),
        Action::impulse(a, cube_a, fast, at_cube),
    ];
    let before = all_bits(&batch);
    assert_eq!(
        action_error(batch.apply_actions(&pair).unwrap_err()),
        (1, "impulse")
    );
    assert_eq!(all_bits(&batch), before);
    batch.apply_actions(&pair[..1]).unwrap();
    assert_ne!(all_bits(&batch), before, "one impulse alone is applied");
    twin.apply_actions(&pair[..1]).unwrap();
    // The refused calls left nothing behind (no wake, no half-applied entry): the batch
    // steps exactly as its twin, which never saw them.
    for _ in 0..30 {
        batch.step().unwrap();
        twin.step().unwrap();
    }
    assert_eq!(all_bits(&batch), all_bits(&twin));
}

/// A handle world `id` never issued: one slot past its last.
fn handle_beyond(batch: &WorldBatch, id: WorldId) -> BodyHandle {
    let max = batch
        .handles(id)
        .unwrap()
        .iter()
        .map(|h| h.index())
        .max()
        .unwrap();
    BodyHandle::from_bits(u64::from(max) + 10)
}

#[test]
fn bad_reads_return_errors_and_write_nothing() {
    let mut batch = knocked_batch();
    batch.step().unwrap();
    let ids = batch.ids();
    let n = batch.body_count(ids[0]).unwrap();
    let n_gone = batch.body_count(ids[2]).unwrap();
    const SENTINEL: f32 = -7.25;
    let expect_length = |r: Result<(), Error>, expected: usize, given: usize| match r {
        Err(Error::Batch(BatchError::BufferLength {
            expected: e,
            given: g,
            ..
        })) => assert_eq!((e, g), (expected, given)),
        other => panic!("expected a length error, got {other:?}"),
    };
    for len in [0, n * POSE_FLOATS - 1, n * POSE_FLOATS + 1] {
        let mut buf = vec![SENTINEL; len];
        expect_length(batch.read_poses(ids[0], &mut buf), n * POSE_FLOATS, len);
        assert!(buf.iter().all(|&x| x == SENTINEL), "nothing written");
    }
    let mut buf = vec![SENTINEL; n * POSE_FLOATS];
    expect_length(
        batch.read_velocities(ids[0], &mut buf),
        n * VELOCITY_FLOATS,
        n * POSE_FLOATS,
    );
    assert!(buf.iter().all(|&x| x == SENTINEL));
    let total = batch.all_poses_len();
    let mut buf = vec![SENTINEL; total + POSE_FLOATS];
    expect_length(batch.read_all_poses(&mut buf), total, total + POSE_FLOATS);
    assert!(buf.iter().all(|&x| x == SENTINEL));

    // Strides: too short for the largest world, and a buffer not a whole number of rows.
    let widest = batch.max_body_count() * POSE_FLOATS;
    let mut buf = vec![SENTINEL; ids.len() * (widest - 1)];
    match batch.read_all_poses_strided(&mut buf, widest - 1) {
        Err(Error::Batch(BatchError::Stride { stride, needed, .. })) => {
            assert_eq!((stride, needed), (widest - 1, widest))
        }
        other => panic!("expected a stride error, got {other:?}"),
    }
    assert!(buf.iter().all(|&x| x == SENTINEL));
    let mut buf = vec![SENTINEL; ids.len() * widest - 1];
    expect_length(
        batch.read_all_poses_strided(&mut buf, widest),
        ids.len() * widest,
        ids.len() * widest - 1,
    );
    assert!(buf.iter().all(|&x| x == SENTINEL));
    // A good strided read: each row starts with its world's poses, the rest is untouched.
    let stride = widest + 3;
    let mut buf = vec![SENTINEL; ids.len() * stride];
    batch.read_all_poses_strided(&mut buf, stride).unwrap();
    for (row, &id) in buf.chunks(stride).zip(&ids) {
        let m = batch.body_count(id).unwrap() * POSE_FLOATS;
        let mut own = vec![0.0; m];
        batch.read_poses(id, &mut own).unwrap();
        assert_eq!(&row[..m], &own[..]);
        assert!(row[m..].iter().all(|&x| x == SENTINEL));
    }
    let vstride = batch.max_body_count() * VELOCITY_FLOATS;
    let mut vbuf = vec![SENTINEL; ids.len() * vstride];
    batch
        .read_all_velocities_strided(&mut vbuf, vstride)
        .unwrap();
    let mut packed = vec![SENTINEL; batch.all_velocities_len()];
    batch.read_all_velocities(&mut packed).unwrap();
    assert!(packed.iter().all(|&x| x != SENTINEL));

    // A removed world's id, and one this batch never issued.
    let gone = ids[2];
    batch.remove_world(gone).unwrap();
    let mut buf = vec![SENTINEL; n * POSE_FLOATS];
    assert_eq!(
        batch.read_poses(gone, &mut buf),
        Err(Error::Batch(BatchError::RemovedWorld(gone)))
    );
    let mut big = WorldBatch::new(Backend::Cpu);
    for _ in 0..20 {
        big.add_world(WorldSpec::new(WorldConfig::default()))
            .unwrap();
    }
    let foreign = big.ids()[15];
    assert_eq!(
        batch.read_poses(foreign, &mut buf),
        Err(Error::Batch(BatchError::UnknownWorld(foreign)))
    );
    assert!(buf.iter().all(|&x| x == SENTINEL));
    // The removed world is gone from the whole-batch reads.
    assert_eq!(batch.len(), ids.len() - 1);
    assert_eq!(batch.all_poses_len(), total - n_gone * POSE_FLOATS);
}

#[test]
fn bad_worlds_are_rejected_with_their_index() {
    let good = WorldSpec::new(WorldConfig::default()).body(BodyDesc::dynamic());
    let bad_body = WorldSpec::new(WorldConfig::default())
        .body(BodyDesc::dynamic())
        .body(BodyDesc::dynamic().density(-1.0));
    let e = WorldBatch::from_specs(Backend::Cpu, vec![good.clone(), bad_body]).unwrap_err();
    assert!(
        matches!(
            &e,
            Error::Batch(BatchError::Build {
                world: 1,
                body: Some(1),
                ..
            })
        ),
        "{e}"
    );
    assert!(e.to_string().contains("density"), "{e}");
    let bad_dt = WorldSpec::new(WorldConfig {
        dt: 0.0,
        ..WorldConfig::default()
    });
    let e =
        WorldBatch::from_specs(Backend::Cpu, vec![good.clone(), good.clone(), bad_dt]).unwrap_err();
    assert!(
        matches!(
            &e,
            Error::Batch(BatchError::Build {
                world: 2,
                body: None,
                ..
            })
        ),
        "{e}"
    );
    let gpu = WorldSpec::new(WorldConfig {
        backend: Backend::Gpu,
        ..WorldConfig::default()
    });
    let mut batch = WorldBatch::from_specs(Backend::Cpu, vec![good]).unwrap();
    let e = batch.add_world(gpu).unwrap_err();
    assert!(
        matches!(&e, Error::Batch(BatchError::BackendMismatch { .. })),
        "{e}"
    );
    assert_eq!(batch.len(), 1, "the failed add left the batch as it was");
}
