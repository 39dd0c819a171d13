//! Which scenes a validation runs: the canonical set (quick), the canonical set plus the
//! large cases (full), or scene files given on the command line; and what the metrics need
//! to know of each.

use std::path::Path;

use tumble::scenes::{self, Scene, SceneCheck};
use tumble_geometry::Vec3;

use crate::scene_info::{BodyInfo, SceneInfo};

/// Height of the large pyramid of the full run: the thesis-scale "extreme stacking" case,
/// 4,900 cubes.
pub const LARGE_PYRAMID_HEIGHT: usize = 24;

/// The scenes of a quick run: the canonical list.
pub fn quick_scenes() -> Vec<Scene> {
    scenes::canonical()
}

/// The scenes too slow for a quick run's default set: the large pyramid.
pub fn large_scenes() -> Vec<Scene> {
    vec![scenes::pyramid(LARGE_PYRAMID_HEIGHT)]
}

/// The scenes of a full run: the canonical list plus the large ones.
pub fn full_scenes() -> Vec<Scene> {
    let mut list = scenes::canonical();
    list.extend(large_scenes());
    list
}

/// Loads and validates scene files; the error names the file.
pub fn load_scene_files(paths: &[impl AsRef<Path>]) -> Result<Vec<Scene>, String> {
    paths
        .iter()
        .map(|p| {
            let p = p.as_ref();
            let text =
                std::fs::read_to_string(p).map_err(|e| format!("--scene {}: {e}", p.display()))?;
            Scene::from_json(&text).map_err(|e| format!("--scene {}: {e}", p.display()))
        })
        .collect()
}

/// Keeps the scenes whose name contains `filter` (case-insensitive).
pub fn filter_scenes(list: Vec<Scene>, filter: Option<&str>) -> Vec<Scene> {
    match filter {
        None => list,
        Some(f) => {
            let f = f.to_ascii_lowercase();
            list.into_iter()
                .filter(|s| s.name.to_ascii_lowercase().contains(&f))
                .collect()
        }
    }
}

/// The metrics' view of a scene: sizes, masses (density times volume), rest poses.
pub fn scene_info(scene: &Scene) -> SceneInfo {
    SceneInfo {
        name: scene.name.clone(),
        bodies: scene
            .bodies
            .iter()
            .map(|b| {
                let mass = if b.is_dynamic() { b.mass() } else { 0.0 };
                BodyInfo::cuboid(b.is_dynamic(), Vec3::from(b.half_extents), mass, b.pose())
            })
            .collect(),
        gravity: Vec3::from(scene.gravity),
        dt: scene.dt,
    }
}

/// True when the check describes bodies that end the run at rest: standing structures,
/// settled piles, separated overlaps, fallen dominoes.
fn check_expects_rest(check: &SceneCheck) -> bool {
    match check {
        SceneCheck::MaxDrift { .. }
        | SceneCheck::StaysPut { .. }
        | SceneCheck::Contained { .. }
        | SceneCheck::Separates { .. }
        | SceneCheck::Topples { .. } => true,
        SceneCheck::All { checks } => {
            checks.iter().any(check_expects_rest) && !checks.iter().any(check_expects_motion)
        }
        _ => false,
    }
}

/// True when the check describes bodies that keep moving (sliding, free spinning).
fn check_expects_motion(check: &SceneCheck) -> bool {
    match check {
        SceneCheck::Slides { .. } | SceneCheck::AngularMomentum { .. } => true,
        SceneCheck::All { checks } => checks.iter().any(check_expects_motion),
        _ => false,
    }
}

/// The bodies whose motion over the last second counts as jitter: every dynamic body when
/// the scene's check expects a rest state, none otherwise.
pub fn should_rest(scene: &Scene) -> Vec<bool> {
    let rest = check_expects_rest(&scene.check);
    scene
        .bodies
        .iter()
        .map(|b| rest && b.is_dynamic())
        .collect()
}

/// A file-name-safe version of a scene name.
pub fn file_stem(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quick_set_has_at_least_six_scenes_and_the_reference_cases() {
        let list = quick_scenes();
        assert!(list.len() >= 6, "{}", list.len());
        let names: Vec<&str> = list.iter().map(|s| s.name.as_str()).collect();
        assert!(names.iter().any(|n| n.contains("stack")), "{names:?}");
        assert!(names.iter().any(|n| n.contains("mass_ratio")), "{names:?}");
    }

    #[test]
    fn a_filter_reaches_the_large_scenes_even_in_a_quick_run() {
        let name = format!("pyramid_{LARGE_PYRAMID_HEIGHT}");
        assert!(!quick_scenes().iter().any(|s| s.name == name));
        let picked = filter_scenes(full_scenes(), Some(&name));
        assert_eq!(
            picked.len(),
            1,
            "{:?}",
            picked.iter().map(|s| &s.name).collect::<Vec<_>>()
        );
    }

    #[test]
    fn full_set_adds_the_large_pyramid() {
        let full = full_scenes();
        let big = scenes::pyramid_cube_count(LARGE_PYRAMID_HEIGHT);
        assert!(full.iter().any(|s| s.dynamic_count() == big));
    }

    #[test]
    fn a_stack_rests_and_a_ramp_slide_does_not() {
        let stack = scenes::stack(5);
        assert!(should_rest(&stack).iter().filter(|&&r| r).count() == stack.dynamic_count());
        let ramp = scenes::friction_ramp(30.0, 0.3);
        assert!(should_rest(&ramp).iter().all(|&r| !r));
    }

    #[test]
    fn masses_follow_density_and_fixed_bodies_have_none() {
        let scene = scenes::mass_ratio();
        let info = scene_info(&scene);
        for (spec, body) in scene.bodies.iter().zip(&info.bodies) {
            assert_eq!(body.dynamic, spec.is_dynamic());
            let expected = if spec.is_dynamic() {
                spec.density * spec.volume()
            } else {
                0.0
            };
            assert_eq!(body.mass, expected);
        }
        // The scene's point is a 100:1 ratio between its heaviest and lightest bodies.
        let masses: Vec<f32> = info
            .bodies
            .iter()
            .filter(|b| b.dynamic)
            .map(|b| b.mass)
            .collect();
        let ratio = masses.iter().cloned().fold(0.0, f32::max)
            / masses.iter().cloned().fold(f32::INFINITY, f32::min);
        assert!((ratio - 100.0).abs() < 1e-3, "{ratio}");
    }

    #[test]
    fn filter_and_file_errors_name_their_input() {
        let kept = filter_scenes(quick_scenes(), Some("STACK"));
        assert!(!kept.is_empty() && kept.iter().all(|s| s.name.contains("stack")));
        let err = load_scene_files(&["/nonexistent/scene.json"]).unwrap_err();
        assert!(err.contains("/nonexistent/scene.json"), "{err}");
        assert_eq!(file_stem("ramp 30deg/mu0.3"), "ramp_30deg_mu0_3");
    }
}
