//! Scene files as input (docs/errors.md): unknown fields are refused by name, the format
//! version is checked, a body's error names its index and field, every committed scene file
//! loads, and a scene body outside the engine's bounds is refused when the world is built.

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

/// A scene passes its own validation with finite positive numbers, but the engine's bounds
/// refuse a box of 1 um or 2 km half extent, or a centre 1e6 m out, when the world is built;
/// the error names the body's index and the field.
#[test]
fn scene_bodies_outside_the_engine_bounds_are_named_by_index() {
    let cases: [(fn(&mut tumble::scenes::BodySpec), &str); 4] = [
        (|b| b.half_extents[0] = 1e-6, "half_extents.x"),
        (|b| b.position[0] = 1e6, "pose"),
        (|b| b.density = 1e30, "density"),
        (|b| b.linear_velocity[1] = -1e4, "linear_velocity"),
    ];
    for (edit, field) in cases {
        let mut scene = Scene::from_json(&scene_text("", "")).unwrap();
        edit(&mut scene.bodies[1]);
        scene.validate().unwrap();
        let e = World::from_scene(&scene, WorldConfig::default()).unwrap_err();
        let text = e.to_string();
        assert!(matches!(e, Error::InvalidScene(_)), "{e:?}");
        assert!(
            text.contains("bodies[1]") && text.contains(field),
            "{field}: {text}"
        );
    }
    // Gravity out of bounds names the world field.
    let mut scene = Scene::from_json(&scene_text("", "")).unwrap();
    scene.gravity = [0.0, -1e30, 0.0];
    let e = World::from_scene(&scene, WorldConfig::default()).unwrap_err();
    assert_eq!(e.field(), Some("gravity"), "{e}");
}
