//! The canonical scenes' own checks (`SceneCheck`, judged by `CheckTracker`) against Tumble.
//!
//! The CPU backend runs every canonical scene's check for the scene's full length in the
//! stability suite (`canonical_scenes_pass_their_checks` in `tests/src/stability.rs`,
//! instantiated by `tests/tests/stability.rs`). This file adds:
//!
//! - the GPU backends on the small scenes the GPU stability suite (`gpu_stability.rs`) does not
//!   already judge with equal or tighter bounds: the domino chain (`Topples`), the plank on
//!   four cubes (`StaysPut`), both 30-degree ramps (`Slides`), the column at 10 km
//!   (`MaxDrift`), the fast cube (`NoTunneling`) and the overlapping pair (`Separates`). The
//!   column of 20, the 100:1 column and the spinning box are judged there with the stability
//!   suite's thresholds; the pyramid of 12, the wall and the 512-cube pool are left to the CPU
//!   for run time on a software rasterizer (minutes each on lavapipe).
//! - deliberately wrong runs that must fail their scene's check, so that each check is known
//!   to be live against Tumble's states and not only against rapier3d's.
//!
//! Run time on 2 cores with lavapipe: about 70 s for the file while other builds share the
//! cores, 50 s of CPU time; the GPU domino chain (840 steps) is the longest test, about 15 s.
//!
//! GPU tests need a GPU (or lavapipe): without one they print "skipped: no GPU adapter" and
//! pass, unless `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.

use tumble::prelude::*;
use tumble::scenes::{self, Scene, SceneCheck};
use tumble_tests::stability::{judge_run, scene_check, world_config};

/// Runs `scene` on the default CPU configuration but built from `wrong`, a deliberately broken
/// variant, and returns the original scene's verdict on it.
fn judge_wrong(scene: &Scene, wrong: &Scene, config: WorldConfig) -> scenes::CheckReport {
    let report = judge_run(wrong, scene, config, scene.steps);
    println!("{} (deliberately wrong): {report}", scene.name);
    report
}

fn default_cpu() -> WorldConfig {
    world_config(Backend::Cpu, SolverConfig::default())
}

#[test]
fn ramp_cube_without_friction_fails_the_stick_check() {
    // mu 0.7 on 30 degrees sticks (tan 30 = 0.577). With every friction at zero the cube slides
    // at g sin 30 = 4.905 m/s^2, 49 times the 0.1 m/s^2 the Slides check allows around zero.
    let scene = scenes::friction_ramp(30.0, 0.7);
    let mut wrong = scene.clone();
    for body in &mut wrong.bodies {
        body.friction = 0.0;
    }
    let report = judge_wrong(&scene, &wrong, default_cpu());
    assert!(!report.passed, "{report}");
    // The tracker measures the frictionless slide itself: g sin 30 within the check's own
    // 0.1 m/s^2 tolerance.
    let free_slide = scenes::builders::ramp_acceleration(30.0, 0.0);
    assert!(
        (report.measured - free_slide).abs() < 0.1,
        "measured {} m/s^2, frictionless {free_slide}",
        report.measured
    );
}

#[test]
fn dominoes_without_gravity_fail_the_topple_check() {
    // Without gravity nothing pulls a struck domino over: the first one spins away at its
    // initial 1.5 rad/s, the ones it hits are knocked along, and those it does not reach keep
    // their initial upright pose, so the least tilted domino ends far below the 45 degrees the
    // check requires.
    let scene = scenes::dominoes(20);
    let mut wrong = scene.clone();
    wrong.gravity = [0.0; 3];
    let report = judge_wrong(&scene, &wrong, default_cpu());
    assert!(!report.passed, "{report}");
    assert!(report.measured < 10.0, "{report}");
}

#[test]
fn pool_without_walls_fails_the_containment_check() {
    // The same 512 tumbling cubes dropped on the floor alone: the pile spreads, and the cubes
    // knocked outward slide past where the walls stood and off the floor, which ends at the
    // walls' outer faces (the run measures them hundreds of metres below it).
    let scene = scenes::pool(scenes::CANONICAL_POOL);
    let mut wrong = scene.clone();
    // Body 0 is the floor; bodies 1 to 4 are the four walls. They are sunk 1 km below the
    // floor rather than removed, so the body list still matches the scene's.
    for wall in &mut wrong.bodies[1..5] {
        assert!(!wall.is_dynamic(), "the pool's bodies 1 to 4 are its walls");
        wall.position[1] -= 1000.0;
    }
    let report = judge_wrong(&scene, &wrong, default_cpu());
    let SceneCheck::Contained { .. } = scene.check else {
        panic!("the pool has a Contained check");
    };
    // More than a cube's width outside: not a graze of the boundary.
    assert!(!report.passed && report.measured > 1.0, "{report}");
}

#[test]
fn mass_ratio_on_soft_contacts_fails_the_stays_put_check() {
    // Box2D's default contacts, 30 Hz at 4 substeps, are springs a quarter as stiff as the
    // default's 60 Hz: under the 100 kg cube the column's four contacts sink 14.7 cm together
    // (docs/solver.md), three times the check's 5 cm. The default sinks 3.9 cm and passes.
    let scene = scenes::mass_ratio();
    let config = world_config(
        Backend::Cpu,
        SolverConfig {
            substeps: 4,
            contact_hertz: 30.0,
            ..SolverConfig::default()
        },
    );
    let report = judge_wrong(&scene, &scene, config);
    assert!(!report.passed, "{report}");
    assert!(report.measured > 0.1, "{report}");
}

/// The canonical scene named `name`.
fn canonical(name: &str) -> Scene {
    scenes::canonical()
        .into_iter()
        .find(|s| s.name == name)
        .unwrap_or_else(|| panic!("no canonical scene {name}"))
}

/// One `#[test]` per scene: runs the scene's check on the backend for its full length.
macro_rules! gpu_scene_checks {
    ($module:ident, $backend:expr) => {
        mod $module {
            use super::*;

            fn check(name: &str) {
                if tumble_gpu::GpuContext::for_tests().is_none() {
                    return;
                }
                let scene = canonical(name);
                let report = scene_check(&scene, $backend, SolverConfig::default());
                println!("{} on {:?}: {report}", scene.name, $backend);
                assert!(report.passed, "{} on {:?}: {report}", scene.name, $backend);
            }

            #[test]
            fn dominoes_all_topple() {
                check("dominoes_20");
            }
            #[test]
            fn plank_on_four_cubes_stays_put() {
                check("wide_on_small");
            }
            #[test]
            fn ramp_cube_with_mu_0_3_slides_at_coulombs_rate() {
                check("friction_ramp_30deg_mu0.3");
            }
            #[test]
            fn ramp_cube_with_mu_0_7_sticks() {
                check("friction_ramp_30deg_mu0.7");
            }
            #[test]
            fn column_at_10_km_stands() {
                check("far_from_origin_10000");
            }
            #[test]
            fn fast_cube_does_not_tunnel() {
                check("high_speed");
            }
            #[test]
            fn overlapping_cubes_separate() {
                check("overlap_recovery");
            }
        }
    };
}

gpu_scene_checks!(gpu, Backend::Gpu);
gpu_scene_checks!(hybrid, Backend::Hybrid);
