//! Scenes shipped as JSON files under `scenes/`, the on-disk format users write their own in.
//!
//! The files are written by `cargo run -p tumble-scenes --example write_scene_json` from the
//! builders; a test checks that each still equals its builder.

use crate::{Scene, SceneError, friction_ramp, high_speed, stack};

/// The embedded scene files: `(file name, JSON text)`.
pub const EMBEDDED_SCENES: &[(&str, &str)] = &[
    ("stack_20.json", include_str!("../scenes/stack_20.json")),
    (
        "friction_ramp_30deg_mu0.3.json",
        include_str!("../scenes/friction_ramp_30deg_mu0.3.json"),
    ),
    ("high_speed.json", include_str!("../scenes/high_speed.json")),
];

/// The builders the embedded files are written from, in `EMBEDDED_SCENES` order.
pub fn embedded_sources() -> Vec<Scene> {
    vec![stack(20), friction_ramp(30.0, 0.3), high_speed()]
}

/// Parses every embedded scene file.
pub fn embedded() -> Result<Vec<Scene>, SceneError> {
    EMBEDDED_SCENES
        .iter()
        .map(|(_, text)| Scene::from_json(text))
        .collect()
}
