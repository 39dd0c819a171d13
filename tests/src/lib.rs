//! Shared helpers for the cross-check and stability tests.
//!
//! The stability suite lives here as plain functions of `(Backend, SolverConfig)`;
//! [`stability_suite!`] turns them into `#[test]`s for one backend and solver, so the CPU,
//! GPU and hybrid backends all run the same checks.

pub mod bad_input;
pub mod effect_bounds;
pub mod facade;
pub mod gpu_scene;
pub mod gpu_solver_util;
pub mod scene_support;
pub mod shader_checks;
pub mod stability;

/// Instantiates the stability suite as a test module `$name` for `$backend` and `$solver`
/// (both expressions, written with full paths, e.g. `tumble::Backend::Cpu`).
#[macro_export]
macro_rules! stability_suite {
    ($name:ident, $backend:expr, $solver:expr) => {
        mod $name {
            fn backend() -> tumble::Backend {
                $backend
            }
            fn solver() -> tumble::SolverConfig {
                $solver
            }
            #[test]
            fn column_of_20_cubes_stands_10_s() {
                $crate::stability::column_stands(backend(), solver(), 20);
            }
            #[test]
            fn column_of_30_cubes_stands_10_s() {
                $crate::stability::column_stands(backend(), solver(), 30);
            }
            #[test]
            fn pyramid_of_650_cubes_stands_10_s() {
                $crate::stability::pyramid_stands(backend(), solver());
            }
            #[test]
            fn cube_100x_denser_stands_on_three() {
                $crate::stability::heavy_cube_stands(backend(), solver());
            }
            #[test]
            fn box_10x_wider_stands_on_four_cubes() {
                $crate::stability::wide_box_stands(backend(), solver());
            }
            #[test]
            fn box_with_mu_half_sticks_on_a_20_degree_ramp() {
                $crate::stability::ramp_box_sticks(backend(), solver());
            }
            #[test]
            fn box_with_mu_0_2_slides_at_coulombs_rate() {
                $crate::stability::ramp_box_slides(backend(), solver());
            }
            #[test]
            fn overlapping_boxes_separate_within_the_push_out_cap() {
                $crate::stability::overlapping_boxes_separate(backend(), solver());
            }
            #[test]
            fn fast_cube_does_not_pass_a_thin_floor() {
                $crate::stability::fast_box_does_not_tunnel(backend(), solver());
            }
            #[test]
            fn spinning_box_keeps_its_angular_momentum() {
                $crate::stability::spinning_box_keeps_momentum(backend(), solver());
            }
            #[test]
            fn far_column_stands_like_near_column() {
                $crate::stability::far_column_stands_like_near(backend(), solver());
            }
            #[test]
            fn canonical_scenes_pass_their_checks() {
                $crate::stability::canonical_scenes_pass_their_checks(backend(), solver());
            }
            #[test]
            fn bad_bodies_are_rejected() {
                $crate::bad_input::bad_bodies_are_rejected(backend(), solver());
            }
            #[test]
            fn bad_updates_are_rejected() {
                $crate::bad_input::bad_updates_are_rejected(backend(), solver());
            }
            #[test]
            fn stale_handles_are_rejected() {
                $crate::bad_input::stale_handles_are_rejected(backend(), solver());
            }
            #[test]
            fn bad_configs_are_rejected() {
                $crate::bad_input::bad_configs_are_rejected(backend(), solver());
            }
            #[test]
            fn out_of_bound_updates_are_rejected() {
                $crate::bad_input::out_of_bound_updates_are_rejected(backend(), solver());
            }
        }
    };
}

/// The user guide's examples (docs/guide.md), compiled and run as doctests: the guide is not
/// part of any published crate, so this crate, which is never published, runs them.
#[cfg(doctest)]
#[doc = include_str!("../../docs/guide.md")]
pub struct GuideDoctests;
