//! Scene files as input (docs/errors.md): unknown fields are refused by name, the format
//! version is checked, a body's error names its index and field, every committed scene file
//! loads, and a scene value outside the engine's bounds is refused when the scene is read.

use std::path::Path;

use tumble::prelude::*;
use tumble::scenes::{FORMAT_VERSION, Scene, SceneError};

/// A floor and one valid box; `top` is spliced before the scene's fields, `body` into the
/// box's object.
fn scene_text(top: &str, body: &str) -> String {
    format!(
        r#"{{
        {top}
        "name": "two_boxes",
        "bodies": [
            {{ "kind": "Fixed", "half_extents": [5, 0.5, 5], "position": [0, -0.5, 0] }},
            {{ "half_extents": [0.5, 0.5, 0.5], "position": [0, 2, 0] {body} }}
        ]
    }}"#
    )
}

#[test]
fn a_valid_scene_loads_with_and_without_a_version() {
    let plain = Scene::from_json(&scene_text("", "")).unwrap();
    assert_eq!(plain.version, FORMAT_VERSION);
    let versioned = Scene::from_json(&scene_text(r#""version": 1,"#, "")).unwrap();
    assert_eq!(plain, versioned);
    // A body field given explicitly is read, not defaulted.
    let s = Scene::from_json(&scene_text("", r#", "friction": 0.25"#)).unwrap();
    assert_eq!(s.bodies[1].friction, 0.25);
}

#[test]
fn a_misspelt_body_field_is_an_error_naming_it_and_the_body() {
    // Before, `frcition` was ignored and the body got the default friction 0.6.
    let e = Scene::from_json(&scene_text("", r#", "frcition": 0.1"#)).unwrap_err();
    match &e {
        SceneError::Body { index, source } => {
            assert_eq!(*index, 1);
            assert!(source.to_string().contains("frcition"), "{source}");
        }
        other => panic!("expected a body error, got {other:?}"),
    }
    assert!(e.to_string().contains("bodies[1]"), "{e}");
}

#[test]
fn unknown_top_level_and_check_fields_are_errors_naming_them() {
    let e = Scene::from_json(&scene_text(r#""gravty": [0, -9.81, 0],"#, "")).unwrap_err();
    assert!(e.to_string().contains("gravty"), "{e}");
    let e = Scene::from_json(&scene_text(
        r#""check": { "kind": "StaysPut", "meters": 0.1, "metres": 0.2 },"#,
        "",
    ))
    .unwrap_err();
    assert!(e.to_string().contains("metres"), "{e}");
    // The same check without the stray field loads.
    Scene::from_json(&scene_text(
        r#""check": { "kind": "StaysPut", "meters": 0.1 },"#,
        "",
    ))
    .unwrap();
}

#[test]
fn unknown_versions_are_refused() {
    for v in ["2", "0", "\"1\"", "1.5"] {
        let e = Scene::from_json(&scene_text(&format!(r#""version": {v},"#), "")).unwrap_err();
        assert!(
            matches!(e, SceneError::UnsupportedVersion(_)),
            "version {v}: {e:?}"
        );
        assert!(e.to_string().contains("version"), "{e}");
    }
    // A later version with a field this build does not know reports the version, the
    // cause, not the field.
    let e = Scene::from_json(&scene_text(r#""version": 2, "joints": [],"#, "")).unwrap_err();
    assert!(matches!(e, SceneError::UnsupportedVersion(_)), "{e:?}");
}

#[test]
fn a_bad_body_value_names_the_body_and_the_field() {
    let e = Scene::from_json(&scene_text("", r#", "density": -1"#)).unwrap_err();
    assert!(e.to_string().contains("bodies[1].density"), "{e}");
    let e =
        Scene::from_json(&scene_text("", r#", "linear_velocity": [0, "fast", 0]"#)).unwrap_err();
    assert!(e.to_string().contains("bodies[1]"), "{e}");
}

/// Every JSON scene committed under `crates/tumble-scenes/scenes/` loads, carries the
/// current version, and builds a world.
#[test]
fn every_committed_scene_file_loads() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../crates/tumble-scenes/scenes");
    let mut loaded = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "json") {
            let text = std::fs::read_to_string(&path).unwrap();
            let scene = Scene::from_json(&text).unwrap_or_else(|e| panic!("{path:?}: {e}"));
            assert!(
                text.contains("\"version\": 1"),
                "{path:?} lacks its version"
            );
            World::from_scene(&scene, WorldConfig::default())
                .unwrap_or_else(|e| panic!("{path:?}: {e}"));
            loaded += 1;
        }
    }
    // stack_20, friction_ramp_30deg_mu0.3 and high_speed.
    assert!(loaded >= 3, "only {loaded} scene files found in {dir:?}");
}

/// The world's ranges (`tumble_solver::bounds`) apply when a scene is read: a box of 1 um or
/// 2 km half extent, a centre 1e6 m out, a density of 1e30, a speed of 1e4 m/s, a spin past
/// what the default substeps carry, a friction of 50, a `dt` of 1e-30 s or a gravity of 1e30
/// m/s^2 is refused by `Scene::validate` (and so by `Scene::from_json`) naming the body's index
/// and the field, where before the scene was accepted and only `World::from_scene` refused it.
/// A scene that validates builds a world.
#[test]
fn scene_values_outside_the_engine_bounds_are_refused_when_read() {
    type Edit = fn(&mut Scene);
    let cases: [(Edit, &str); 9] = [
        (
            |s| s.bodies[1].half_extents[0] = 1e-6,
            "bodies[1].half_extents.x",
        ),
        (
            |s| s.bodies[1].half_extents[2] = 2e3,
            "bodies[1].half_extents.z",
        ),
        (|s| s.bodies[1].position[0] = 1e6, "bodies[1].position"),
        (|s| s.bodies[1].density = 1e30, "bodies[1].density"),
        (
            |s| s.bodies[1].linear_velocity[1] = -1e4,
            "bodies[1].linear_velocity",
        ),
        (
            |s| s.bodies[1].angular_velocity[1] = 1e5,
            "bodies[1].angular_velocity",
        ),
        (|s| s.bodies[1].friction = 50.0, "bodies[1].friction"),
        (|s| s.dt = 1e-30, "dt"),
        (|s| s.gravity = [0.0, -1e30, 0.0], "gravity"),
    ];
    for (edit, field) in cases {
        let mut scene = Scene::from_json(&scene_text("", "")).unwrap();
        edit(&mut scene);
        let e = scene.validate().unwrap_err();
        match &e {
            SceneError::InvalidField { field: f, .. } => assert_eq!(f, field, "{e}"),
            other => panic!("{field}: {other:?}"),
        }
        // Through the file format too, and the world refuses the same scene.
        let text = scene.to_json();
        assert!(
            Scene::from_json(&text)
                .unwrap_err()
                .to_string()
                .contains(field)
        );
        let refused = World::from_scene(&scene, WorldConfig::default()).unwrap_err();
        assert!(matches!(refused, Error::InvalidScene(_)), "{refused:?}");
    }
    // The fuzz seed of docs/reliability.md's finding 3 (dt 1e-30, half extents 1e-30 and
    // 1e30, a position of 3e38): refused when read, naming dt, the first bad field.
    let seed = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../fuzz/corpus/scene_from_json/seed_extreme_values.json"),
    )
    .unwrap();
    let e = Scene::from_json(&seed).unwrap_err();
    assert!(
        matches!(&e, SceneError::InvalidField { field, .. } if field == "dt"),
        "{e}"
    );
    // At the edges of the ranges the scene is read and the world is built.
    let mut scene = Scene::from_json(&scene_text("", "")).unwrap();
    scene.bodies[1].half_extents = [1e-3, 1e3, 0.5];
    scene.bodies[1].density = 1e5;
    scene.bodies[1].friction = 10.0;
    scene.bodies[1].linear_velocity = [0.0, -400.0, 0.0];
    scene.dt = 0.1;
    scene.validate().unwrap();
    World::from_scene(&scene, WorldConfig::default()).unwrap();
}
