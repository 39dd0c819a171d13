//! The canonical scenes: valid data that survives JSON, sensible initial configurations, the
//! same scene in rapier3d, and checks that pass and fail when they should.
//!
//! The checks here judge rapier3d's runs, which shows the criteria are achievable and that the
//! tracker reads a run correctly. Tumble's runs face the same checks elsewhere: every canonical
//! scene for its full length on the CPU in the stability suite
//! (`canonical_scenes_pass_their_checks` in `tests/src/stability.rs`), the small scenes on the
//! GPU backends and deliberately wrong Tumble runs that must fail in
//! `tests/tests/scene_checks.rs`.

use rapier3d::prelude::CoefficientCombineRule;
use tumble_broad::sweep_and_prune_filtered;
use tumble_geometry::{Aabb, Real};
use tumble_scenes::{
    BodyKind, BodySpec, BodyState, CheckTracker, EMBEDDED_SCENES, RapierOptions, RapierWorld,
    Scene, SceneCheck, SceneError, build_rapier, build_rapier_with, builders::ramp_acceleration,
    canonical, cuboid_penetration, embedded_sources, friction_ramp, high_speed, overlap_recovery,
    pyramid, pyramid_cube_count, spinning_box, stack,
};

/// Runs `world` for `steps` steps, feeding every state to a tracker of `scene`.
fn run_rapier(scene: &Scene, world: &mut RapierWorld, steps: u32) -> CheckTracker {
    let mut tracker = CheckTracker::new(scene);
    for _ in 0..steps {
        world.step();
        tracker.observe(&world.body_states()).unwrap();
    }
    tracker
}

fn field_of(err: SceneError) -> String {
    match err {
        SceneError::InvalidField { field, .. } => field,
        other => panic!("expected an InvalidField error, got {other}"),
    }
}

#[test]
fn every_canonical_scene_is_valid_and_round_trips_through_json() {
    let scenes = canonical();
    let mut names: Vec<&str> = scenes.iter().map(|s| s.name.as_str()).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), scenes.len(), "scene names must be unique");
    for scene in &scenes {
        scene.validate().unwrap();
        assert!(
            scene.dynamic_count() > 0,
            "{} has nothing to simulate",
            scene.name
        );
        let back = Scene::from_json(&scene.to_json()).unwrap();
        // serde_json writes the shortest decimal that reads back as the same f32: bit-exact.
        assert_eq!(&back, scene, "{} changed through JSON", scene.name);
    }
}

#[test]
fn embedded_json_files_equal_their_builders() {
    let built = embedded_sources();
    assert_eq!(built.len(), EMBEDDED_SCENES.len());
    for ((file, text), scene) in EMBEDDED_SCENES.iter().zip(&built) {
        assert_eq!(*file, format!("{}.json", scene.name));
        assert_eq!(
            &Scene::from_json(text).unwrap(),
            scene,
            "{file} is stale: regenerate with the write_scene_json example"
        );
    }
}

#[test]
fn omitted_fields_take_documented_defaults() {
    let text = r#"{
        "name": "one_box",
        "bodies": [ { "half_extents": [0.5, 0.5, 0.5], "position": [0, 2, 0] } ]
    }"#;
    let scene = Scene::from_json(text).unwrap();
    assert_eq!(scene.gravity, [0.0, -9.81, 0.0]);
    assert_eq!(scene.dt, 1.0 / 60.0);
    assert_eq!(scene.check, SceneCheck::Finite);
    let body = &scene.bodies[0];
    assert_eq!(body.kind, BodyKind::Dynamic);
    assert_eq!(body.rotation, [0.0, 0.0, 0.0, 1.0]);
    assert_eq!(
        (body.density, body.friction, body.restitution),
        (1.0, 0.6, 0.0)
    );
    assert_eq!(body.mass(), 1.0);
}

#[test]
fn validation_names_the_bad_field() {
    let base = stack(3);
    let bad = |edit: &dyn Fn(&mut Scene)| {
        let mut s = base.clone();
        edit(&mut s);
        field_of(s.validate().unwrap_err())
    };
    assert_eq!(bad(&|s| s.dt = 0.0), "dt");
    assert_eq!(bad(&|s| s.dt = Real::NAN), "dt");
    assert_eq!(bad(&|s| s.gravity[1] = Real::INFINITY), "gravity[1]");
    assert_eq!(
        bad(&|s| s.bodies[2].half_extents[1] = -0.5),
        "bodies[2].half_extents[1]"
    );
    assert_eq!(
        bad(&|s| s.bodies[1].half_extents[0] = 0.0),
        "bodies[1].half_extents[0]"
    );
    assert_eq!(
        bad(&|s| s.bodies[3].half_extents[2] = Real::NAN),
        "bodies[3].half_extents[2]"
    );
    assert_eq!(
        bad(&|s| s.bodies[1].position[0] = Real::NAN),
        "bodies[1].position[0]"
    );
    assert_eq!(
        bad(&|s| s.bodies[1].rotation = [0.0, 0.0, 0.0, 2.0]),
        "bodies[1].rotation"
    );
    assert_eq!(
        bad(&|s| s.bodies[2].angular_velocity[2] = Real::NAN),
        "bodies[2].angular_velocity[2]"
    );
    assert_eq!(bad(&|s| s.bodies[2].density = 0.0), "bodies[2].density");
    assert_eq!(bad(&|s| s.bodies[2].friction = -0.1), "bodies[2].friction");
    assert_eq!(
        bad(&|s| s.bodies[2].restitution = 1.5),
        "bodies[2].restitution"
    );
    assert_eq!(
        bad(&|s| s.check = SceneCheck::MaxDrift { meters: -1.0 }),
        "check.meters"
    );
    // A fixed body's density is unused, but the world checks it whatever the kind
    // (`tumble_solver::Body::new`), so the scene refuses zero there too: a scene that reads
    // must build.
    assert_eq!(bad(&|s| s.bodies[0].density = 0.0), "bodies[0].density");
    // The message carries the value too.
    let mut s = base.clone();
    s.bodies[2].half_extents[1] = -0.5;
    let msg = s.validate().unwrap_err().to_string();
    assert!(
        msg.contains("bodies[2].half_extents[1]") && msg.contains("-0.5"),
        "{msg}"
    );
}

#[test]
fn from_json_rejects_invalid_values_and_broken_text() {
    let zero_dt = r#"{ "name": "x", "dt": 0.0, "bodies": [] }"#;
    assert_eq!(field_of(Scene::from_json(zero_dt).unwrap_err()), "dt");
    let negative =
        r#"{ "name": "x", "bodies": [ { "half_extents": [1, -1, 1], "position": [0, 0, 0] } ] }"#;
    assert_eq!(
        field_of(Scene::from_json(negative).unwrap_err()),
        "bodies[0].half_extents[1]"
    );
    // NaN cannot be written in JSON; serializing it gives `null`, which must not load (the
    // error names the body).
    let mut nan = stack(1);
    nan.bodies[1].position[1] = Real::NAN;
    assert!(matches!(
        Scene::from_json(&nan.to_json()),
        Err(SceneError::Body { index: 1, .. })
    ));
    assert!(matches!(
        Scene::from_json("{ not json"),
        Err(SceneError::Json(_))
    ));
}

#[test]
fn pyramid_layers_are_squares_of_cubes() {
    for (h, cubes) in [(1, 1), (2, 5), (12, 650), (24, 4900), (50, 42925)] {
        assert_eq!(pyramid_cube_count(h), cubes);
        let scene = pyramid(h);
        assert_eq!(scene.dynamic_count(), cubes, "pyramid({h})");
        assert_eq!(scene.bodies.len(), cubes + 1, "pyramid({h}) has one floor");
    }
    // Layer k from the top holds k^2 cubes at height (h - k) + 0.5.
    let h = 6;
    let scene = pyramid(h);
    for k in 1..=h {
        let y = (h - k) as Real + 0.5;
        let n = scene.bodies[1..]
            .iter()
            .filter(|b| (b.position[1] - y).abs() < 1e-4)
            .count();
        assert_eq!(n, k * k, "layer {k} of pyramid({h})");
    }
}

#[test]
fn builders_start_without_overlap() {
    // Touching is allowed (depth 0, up to f32 round-off of positions near 10 km: 1e-3 m);
    // only overlap_recovery starts overlapping on purpose.
    const TOUCH_TOLERANCE: Real = 2e-3;
    for scene in canonical()
        .into_iter()
        .filter(|s| s.name != "overlap_recovery")
    {
        let aabbs: Vec<Aabb> = scene
            .bodies
            .iter()
            .map(|b| b.cuboid().aabb(&b.pose(), 0.0))
            .collect();
        let is_static: Vec<bool> = scene.bodies.iter().map(|b| !b.is_dynamic()).collect();
        for (i, j) in sweep_and_prune_filtered(&aabbs, &is_static).unwrap() {
            let (a, b) = (&scene.bodies[i as usize], &scene.bodies[j as usize]);
            let depth = cuboid_penetration(&a.cuboid(), &a.pose(), &b.cuboid(), &b.pose());
            assert!(
                depth <= TOUCH_TOLERANCE,
                "{}: bodies {i} and {j} overlap by {depth}",
                scene.name
            );
        }
    }
    let overlap = overlap_recovery();
    let (a, b) = (&overlap.bodies[1], &overlap.bodies[2]);
    let depth = cuboid_penetration(&a.cuboid(), &a.pose(), &b.cuboid(), &b.pose());
    assert!(
        (depth - 0.5).abs() < 1e-5,
        "the two cubes must start half overlapping, got {depth}"
    );
}

#[test]
fn ramp_expectation_follows_coulomb() {
    // 30 degrees, mu 0.3: g (0.5 - 0.3 * 0.866) = 2.356 m/s^2; mu 0.7 > tan 30 sticks.
    assert!((ramp_acceleration(30.0, 0.3) - 2.3563).abs() < 1e-3);
    assert_eq!(ramp_acceleration(30.0, 0.7), 0.0);
    assert!(
        (ramp_acceleration(90.0, 0.5) - 9.81).abs() < 1e-4,
        "a vertical wall is free fall"
    );
    let scene = friction_ramp(30.0, 0.3);
    let (ramp, cube) = (&scene.bodies[0], &scene.bodies[1]);
    // The cube rests on the ramp's top face: touching, not overlapping, not floating.
    let depth = cuboid_penetration(&ramp.cuboid(), &ramp.pose(), &cube.cuboid(), &cube.pose());
    assert!(
        depth.abs() < 1e-5,
        "cube must touch the ramp, depth {depth}"
    );
}

#[test]
fn rapier_builder_copies_sizes_masses_and_steps_finite() {
    for scene in canonical() {
        let mut world = build_rapier(&scene);
        assert_eq!(world.handles.len(), scene.bodies.len(), "{}", scene.name);
        assert_eq!(world.integration_parameters.dt, scene.dt);
        for (spec, mass) in scene.bodies.iter().zip(world.body_masses()) {
            if spec.is_dynamic() {
                let expected = spec.density * spec.volume();
                assert!(
                    ((mass - expected) / expected).abs() < 1e-4,
                    "{}: rapier mass {mass}, expected {expected}",
                    scene.name
                );
            }
        }
        for (handle, spec) in world.handles.iter().zip(&scene.bodies) {
            let collider = &world.colliders[world.bodies[*handle].colliders()[0]];
            assert_eq!(collider.friction(), spec.friction);
            assert_eq!(
                collider.friction_combine_rule(),
                CoefficientCombineRule::GeometricMean
            );
            let he = collider
                .shape()
                .as_cuboid()
                .unwrap()
                .half_extents
                .to_array();
            assert_eq!(he, spec.half_extents);
        }
        // A few steps of every scene, the big ones included, must stay finite.
        for _ in 0..5 {
            world.step();
        }
        assert!(
            world.body_states().iter().all(BodyState::is_finite),
            "{}",
            scene.name
        );
    }
}

#[test]
fn rapier_passes_the_small_scenes_checks() {
    // A mature solver passes these, so the criteria are achievable as written.
    for scene in [
        friction_ramp(30.0, 0.3),
        friction_ramp(30.0, 0.7),
        overlap_recovery(),
        high_speed(),
        spinning_box(),
    ] {
        let mut world = build_rapier(&scene);
        let report = run_rapier(&scene, &mut world, scene.steps).finish();
        assert!(report.passed, "{}: {report}", scene.name);
    }
}

#[test]
fn checks_fail_when_the_physics_is_wrong() {
    // Dropping the gyroscopic term keeps the angular velocity fixed instead of the angular
    // momentum: the spinning box must then fail its 1% momentum bound.
    let scene = spinning_box();
    let mut world = build_rapier(&scene);
    world.bodies[world.handles[0]].enable_gyroscopic_forces(false);
    let report = run_rapier(&scene, &mut world, scene.steps).finish();
    assert!(!report.passed && report.measured > 0.05, "{report}");

    // A ramp run with the wrong friction slides at the wrong rate: mu 0.4 instead of 0.3 is
    // 0.85 m/s^2 slower, far past the 0.1 tolerance.
    let scene = friction_ramp(30.0, 0.3);
    let mut wrong = scene.clone();
    for b in &mut wrong.bodies {
        b.friction = 0.4;
    }
    let mut world = build_rapier(&wrong);
    let report = run_rapier(&scene, &mut world, scene.steps).finish();
    assert!(!report.passed, "{report}");
    assert!(
        (report.measured - ramp_acceleration(30.0, 0.4)).abs() < 0.1,
        "{report}"
    );
}

#[test]
fn tracker_measures_drift_tunneling_and_non_finite_states() {
    let scene = stack(2); // MaxDrift 1 cm
    let start: Vec<BodyState> = scene.bodies.iter().map(BodyState::initial).collect();
    let mut tracker = CheckTracker::new(&scene);
    let mut moved = start.clone();
    moved[2].position[1] -= 0.3; // sinking is not horizontal drift
    moved[2].position[0] += 0.006;
    tracker.observe(&moved).unwrap();
    let ok = tracker.finish();
    assert!(ok.passed && (ok.measured - 0.006).abs() < 1e-6, "{ok}");
    // Horizontal drift sqrt(6^2 + 8.5^2) = 10.4 mm: past the 1 cm bound.
    moved[2].position[2] += 0.0085;
    tracker.observe(&moved).unwrap();
    assert!(!tracker.finish().passed);
    moved[1].position[0] = Real::NAN;
    tracker.observe(&moved).unwrap();
    assert!(tracker.finish().detail.contains("non-finite"));
    assert!(
        tracker.observe(&moved[..2]).is_err(),
        "one state per body is required"
    );

    let scene = high_speed();
    let mut tracker = CheckTracker::new(&scene);
    let mut through: Vec<BodyState> = scene.bodies.iter().map(BodyState::initial).collect();
    through[1].position[1] = -0.5;
    tracker.observe(&through).unwrap();
    let report = tracker.finish();
    assert!(!report.passed && report.measured == -0.5, "{report}");
}

#[test]
fn spinning_box_spins_about_its_major_axis_without_gravity() {
    let scene = spinning_box();
    let body: &BodySpec = &scene.bodies[0];
    // 1 x 2 x 3 m at density 1.
    assert_eq!(body.mass(), 6.0);
    assert_eq!(scene.gravity, [0.0; 3]);
    // x is the major axis (moment 13/12 m, against 10/12 and 5/12): the spin must be mostly
    // about it, the stable case the check is meant for.
    assert!(
        body.half_extents[0] < body.half_extents[1] && body.half_extents[1] < body.half_extents[2]
    );
    let w = body.angular_velocity;
    assert!(w[0].abs() > 4.0 * w[1].abs().max(w[2].abs()));
}

#[test]
fn rapier_options_reach_the_integration_parameters() {
    let scene = stack(2);
    let options = RapierOptions {
        solver_iterations: 9,
        ..Default::default()
    };
    let mut world = build_rapier_with(&scene, &options);
    assert_eq!(world.integration_parameters.num_solver_iterations, 9);
    world.set_solver_iterations(3);
    assert_eq!(world.integration_parameters.num_solver_iterations, 3);
    // Sleep is off by default: a resting stack stays awake and is measured on every step.
    for _ in 0..120 {
        world.step();
    }
    assert!(
        world
            .handles
            .iter()
            .all(|&h| !world.bodies[h].is_sleeping())
    );
}
