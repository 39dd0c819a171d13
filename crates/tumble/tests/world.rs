//! The facade's behaviour: handles, contact reports, scenes, time, bad input. Each test is a
//! small scene of a few bodies and at most a few seconds.

mod common;

use common::*;
use tumble::prelude::*;

#[test]
fn handles_are_never_reused_and_removed_bodies_leave_the_world() {
    let mut w = world();
    let a = w.add_body(BodyDesc::dynamic()).unwrap();
    let b = cube_at(&mut w, 3.0, 0.0, 0.0);
    w.remove_body(a).unwrap();
    let c = cube_at(&mut w, 6.0, 0.0, 0.0);
    assert_ne!(a, c);
    assert_eq!(w.body_count(), 2);
    assert_eq!(w.pose(a), Err(Error::RemovedHandle(a)));
    assert_eq!(w.remove_body(a), Err(Error::RemovedHandle(a)));
    // The survivors kept their own poses through the reshuffle of the dense arrays.
    assert_eq!(w.pose(b).unwrap().translation.x, 3.0);
    assert_eq!(w.pose(c).unwrap().translation.x, 6.0);
}

#[test]
fn removing_the_support_lets_a_resting_box_fall() {
    let mut w = world();
    let ground = floor(&mut w);
    let base = cube_at(&mut w, 0.0, 0.5, 0.0);
    let top = cube_at(&mut w, 0.0, 1.5, 0.0);
    steps(&mut w, 30);
    assert!(w.contact_pairs().contains(&(base, top)));
    w.remove_body(base).unwrap();
    assert!(
        w.contact_pairs()
            .iter()
            .all(|&(a, b)| a != base && b != base)
    );
    // Free fall of 1 m from rest takes sqrt(2 / g) = 0.45 s; after 1 s the top box rests on
    // the floor, its centre half a metre up (within the few millimetres of contact overlap).
    steps(&mut w, 60);
    let y = w.pose(top).unwrap().translation.y;
    assert!((y - 0.5).abs() < 0.01, "y = {y}");
    assert!(w.contact_pairs().contains(&(ground, top)));
}

#[test]
fn contact_pairs_report_touching_bodies_only() {
    let mut w = world();
    let ground = floor(&mut w);
    let resting = cube_at(&mut w, 0.0, 0.5, 0.0);
    let high = cube_at(&mut w, 5.0, 10.0, 0.0);
    w.step().unwrap();
    let pairs = w.contact_pairs();
    assert_eq!(pairs, vec![(ground, resting)]);
    assert!(pairs.iter().all(|&(a, b)| a != high && b != high));
    let stats = w.stats();
    assert_eq!(stats.manifolds, 1);
    assert_eq!(
        stats.contact_points, 4,
        "a cube on a floor touches at its four corners"
    );
    assert!(stats.colors >= 1);
    // The reported impulse over the step carries the weight: m g dt within 1% once settled.
    steps(&mut w, 30);
    let carried: Real = w.contacts()[0].normal_impulse();
    assert!((carried - G * DT).abs() < 0.01 * G * DT, "{carried}");
}

#[test]
fn from_scene_builds_every_body_with_the_scene_time_step() {
    let scene = tumble::scenes::mass_ratio();
    let (w, handles) = World::from_scene(&scene, WorldConfig::default()).unwrap();
    assert_eq!(handles.len(), scene.bodies.len());
    assert_eq!(w.body_count(), scene.bodies.len());
    assert_eq!(w.config().dt, scene.dt);
    for (spec, &h) in scene.bodies.iter().zip(&handles) {
        let p = w.pose(h).unwrap().translation.vector;
        assert_eq!([p.x, p.y, p.z], spec.position);
        let mass = w.mass(h).unwrap();
        if spec.is_dynamic() {
            assert!((mass - spec.mass()).abs() < 1e-4 * spec.mass());
        } else {
            assert!(mass.is_infinite());
        }
    }
    let mut bad = scene.clone();
    bad.dt = -1.0;
    assert!(matches!(
        World::from_scene(&bad, WorldConfig::default()),
        Err(Error::InvalidScene(_))
    ));
}

#[test]
fn time_advances_by_dt_every_step() {
    // 1/64 s is exact in binary, so the time after n steps is exactly n / 64: any drift, a
    // skipped step or a doubled one shows at once.
    let mut w = World::new(WorldConfig {
        dt: 1.0 / 64.0,
        ..Default::default()
    })
    .unwrap();
    w.add_body(BodyDesc::dynamic()).unwrap();
    assert_eq!(w.time(), 0.0);
    for n in 1..=200u32 {
        w.step().unwrap();
        assert_eq!(w.time(), f64::from(n) / 64.0, "after {n} steps");
    }
    // At 60 Hz the f32 step 1/60 is not exact; the time is n times that f32 in f64. A clock
    // summed in f32 would be off by about one f32 ulp of the time per step (1e-6 s near 10 s),
    // far above the 1e-12 relative allowed here for the f64 product.
    let mut w = world();
    let dt = f64::from(w.config().dt);
    for n in 1..=600u32 {
        w.step().unwrap();
        let expected = f64::from(n) * dt;
        assert!(
            (w.time() - expected).abs() <= 1e-12 * expected,
            "after {n} steps: {} s, expected {expected} s",
            w.time()
        );
    }
    // f32(1/60) is 1/60 + 7e-10, so 600 steps are 10 s within 1e-6 s.
    assert!(
        (w.time() - 10.0).abs() < 1e-6,
        "600 steps at 60 Hz are 10 s"
    );
}

#[test]
fn max_penetration_is_the_deepest_overlap_of_the_last_step() {
    let mut w = weightless();
    assert_eq!(w.max_penetration(), 0.0, "no step, no contact");
    // Two unit cubes with centres 0.9 m apart overlap by 0.1 m; the contacts of a step are
    // found at its start, so the first step reports exactly that depth (f32 round-off of the
    // 0.9 m offset, a few 1e-8 m, aside).
    w.add_body(BodyDesc::dynamic()).unwrap();
    cube_at(&mut w, 0.9, 0.0, 0.0);
    w.step().unwrap();
    let depth = w.max_penetration();
    assert!(
        (depth - 0.1).abs() < 1e-5,
        "max_penetration {depth}, overlap 0.1"
    );
    let reported = w.contacts()[0].max_depth();
    assert_eq!(depth, reported, "the stat is the deepest reported point");
    // A second pair overlapping by 0.25 m becomes the deepest.
    cube_at(&mut w, 0.0, 10.0, 0.0);
    cube_at(&mut w, 0.75, 10.0, 0.0);
    w.step().unwrap();
    let depth = w.max_penetration();
    assert!(
        (depth - 0.25).abs() < 1e-5,
        "max_penetration {depth}, overlap 0.25"
    );
    // Apart, it is zero: far apart (no manifold), and 1 cm apart, within the 2 cm speculative
    // margin, where the manifold's points have a negative depth that must not be reported.
    for gap in [5.0, 0.01] {
        let mut w = weightless();
        w.add_body(BodyDesc::dynamic()).unwrap();
        cube_at(&mut w, 1.0 + gap, 0.0, 0.0);
        w.step().unwrap();
        let expect_manifold = gap < tumble::DEFAULT_MARGIN;
        assert_eq!(
            w.contacts().len(),
            usize::from(expect_manifold),
            "gap {gap}"
        );
        assert_eq!(w.max_penetration(), 0.0, "gap {gap}");
    }
}

#[test]
fn set_kinematic_target_rejects_nan_and_stale_handles_and_changes_nothing() {
    let mut w = world();
    floor(&mut w);
    let k = w
        .add_body(
            BodyDesc::kinematic()
                .translation(0.0, 2.0, 0.0)
                .linear_velocity(Vec3::new(0.5, 0.0, 0.0)),
        )
        .unwrap();
    cube_at(&mut w, 3.0, 0.5, 0.0);
    steps(&mut w, 5);
    let snapshot = |w: &World| -> Vec<(Pose, Vec3, Vec3)> {
        w.handles()
            .iter()
            .map(|&h| {
                (
                    w.pose(h).unwrap(),
                    w.linear_velocity(h).unwrap(),
                    w.angular_velocity(h).unwrap(),
                )
            })
            .collect()
    };
    let before = snapshot(&w);
    let nan = Real::NAN;
    let mut bad_rotation = Pose::identity();
    bad_rotation.rotation =
        Rot::new_unchecked(tumble::nalgebra::Quaternion::new(nan, 0.0, 0.0, 0.0));
    for target in [Pose::translation(0.0, nan, 0.0), bad_rotation] {
        let err = w.set_kinematic_target(k, target).unwrap_err();
        assert_eq!(err.field(), Some("pose"), "{err}");
        assert!(err.to_string().contains("NaN"), "the value is named: {err}");
        assert_eq!(snapshot(&w), before);
    }
    // The platform keeps the velocity it had: after one more step it moved 0.5 m/s * dt.
    let x = w.pose(k).unwrap().translation.x;
    w.step().unwrap();
    let moved = w.pose(k).unwrap().translation.x - x;
    assert!((moved - 0.5 * DT).abs() < 1e-6, "moved {moved}");
    // A removed kinematic body: the error names its handle, and nothing else changes.
    let gone = w
        .add_body(BodyDesc::kinematic().translation(-3.0, 2.0, 0.0))
        .unwrap();
    w.remove_body(gone).unwrap();
    let before = snapshot(&w);
    let target = Pose::translation(-3.0, 3.0, 0.0);
    assert_eq!(
        w.set_kinematic_target(gone, target),
        Err(Error::RemovedHandle(gone))
    );
    assert_eq!(snapshot(&w), before);
    assert_eq!(w.body_count(), 3);
}

#[test]
fn body_getters_err_on_removed_handles_and_read_the_right_body() {
    let mut w = weightless();
    let doomed = w.add_body(BodyDesc::dynamic()).unwrap();
    // A 1 x 2 x 3 box of density 2: m = 12, I = diag(13, 10, 5).
    let brick = w
        .add_body(
            BodyDesc::dynamic()
                .cuboid(Vec3::new(0.5, 1.0, 1.5))
                .density(2.0)
                .translation(5.0, 0.0, 0.0)
                .linear_velocity(Vec3::new(1.0, 2.0, 0.0))
                .angular_velocity(Vec3::new(0.5, 0.0, 0.2)),
        )
        .unwrap();
    let wall = w
        .add_body(
            BodyDesc::fixed()
                .cuboid(Vec3::new(0.1, 2.0, 3.0))
                .translation(-5.0, 0.0, 0.0),
        )
        .unwrap();
    // The removal moves the last body (the wall) into the removed one's dense slot.
    w.remove_body(doomed).unwrap();
    let removed = Error::RemovedHandle(doomed);
    assert_eq!(w.kind(doomed), Err(removed.clone()));
    assert_eq!(w.mass(doomed), Err(removed.clone()));
    assert_eq!(w.half_extents(doomed), Err(removed.clone()));
    assert_eq!(w.angular_momentum(doomed), Err(removed.clone()));
    assert_eq!(w.kinetic_energy(doomed), Err(removed));
    // The survivors answer for themselves, not for whoever took the removed slot.
    assert_eq!(w.kind(brick), Ok(BodyKind::Dynamic));
    assert_eq!(w.kind(wall), Ok(BodyKind::Fixed));
    assert!((w.mass(brick).unwrap() - 12.0).abs() < 1e-4);
    assert_eq!(w.mass(wall), Ok(Real::INFINITY));
    assert_eq!(w.half_extents(brick), Ok(Vec3::new(0.5, 1.0, 1.5)));
    assert_eq!(w.half_extents(wall), Ok(Vec3::new(0.1, 2.0, 3.0)));
    // L = I w = (13 * 0.5, 0, 5 * 0.2); E = m v^2 / 2 + w.Iw / 2 = 30 + 1.725.
    let l = w.angular_momentum(brick).unwrap();
    assert!((l - Vec3::new(6.5, 0.0, 1.0)).norm() < 1e-4, "{l}");
    let e = w.kinetic_energy(brick).unwrap();
    assert!((e - 31.725).abs() < 1e-3, "{e}");
    assert_eq!(w.angular_momentum(wall), Ok(Vec3::zeros()));
    assert_eq!(w.kinetic_energy(wall), Ok(0.0));
}

/// An out-of-bound value is an error whose message names the field, the value and the range
/// with its constant, and the world keeps its bodies exactly.
#[test]
fn out_of_bound_values_are_named_with_their_range() {
    let mut w = world();
    let cube = w.add_body(BodyDesc::dynamic()).unwrap();
    let state = |w: &World| {
        (
            w.body_count(),
            w.pose(cube).unwrap(),
            w.linear_velocity(cube).unwrap(),
        )
    };
    let before = state(&w);
    let e = w
        .add_body(BodyDesc::dynamic().cuboid(Vec3::new(0.5, 1e-30, 0.5)))
        .unwrap_err();
    assert_eq!(e.field(), Some("half_extents.y"));
    assert_mentions(&e, &["1e-30", "MIN_HALF_EXTENT"]);
    let e = w.set_linear_velocity(cube, Vec3::new(0.0, 1e6, 0.0));
    assert_mentions(&e.unwrap_err(), &["linear_velocity", "MAX_SPEED"]);
    let e = w.set_pose(cube, Pose::translation(1e6, 0.0, 0.0));
    assert_mentions(&e.unwrap_err(), &["MAX_POSITION"]);
    assert_eq!(state(&w), before);
}

/// Asserts that the message of `e` names every one of `words`.
#[track_caller]
fn assert_mentions(e: &Error, words: &[&str]) {
    let text = e.to_string();
    for word in words {
        assert!(text.contains(word), "no {word:?} in: {text}");
    }
}
