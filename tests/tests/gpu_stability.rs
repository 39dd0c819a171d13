//! The CPU stability suite's checks on `Backend::Gpu` (the whole step on the GPU) and
//! `Backend::Hybrid` (collision on the GPU, solver on the CPU), through the facade, with the
//! default soft-step solver, and the column of 20 and the 100:1 mass ratio with the thesis's
//! Baumgarte solver: the same scenes, the same thresholds, the same code
//! (`tumble_tests::stability`, `tumble_tests::bad_input`).
//!
//! Left out for run time on a software rasterizer: the 30-cube column, the pyramids, the 10x
//! wider box, the column at 10 km and the run of every canonical scene, which together take
//! minutes on lavapipe; all pass on both backends and with both solvers with
//! `tumble_tests::stability_suite!` (docs/gpu-solver.md;
//! `tests/tests/gpu_solver_motion.rs` stands a 20-cube column and a pyramid on the GPU step
//! directly). About 80 s on lavapipe with two test threads; the Baumgarte column
//! of 20 takes 34 s of it on `Backend::Gpu` (60 passes), its mass ratio 17 s.
//!
//! Needs a GPU (or lavapipe): without one every test prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.

use tumble::{Backend, SolverConfig};
use tumble_gpu::GpuContext;
use tumble_tests::{bad_input, stability};

/// True when a GPU is there (or the test must fail because it is not).
fn have_gpu() -> bool {
    GpuContext::for_tests().is_some()
}

/// A test module `$name` running the column of 20 and the 100:1 mass ratio, then each
/// `$test: $check` (a `fn(Backend, SolverConfig)`), on `$backend` with `$solver`, when a GPU is
/// there.
macro_rules! checks {
    ($name:ident, $backend:expr, $solver:expr $(, $test:ident: $check:expr)* $(,)?) => {
        mod $name {
            use super::*;

            checks!(@tests $backend, $solver,
                column_of_20_cubes_stands_10_s: |b, s| stability::column_stands(b, s, 20),
                cube_100x_denser_stands_on_three: stability::heavy_cube_stands,
                $($test: $check,)*
            );
        }
    };
    (@tests $backend:expr, $solver:expr, $($test:ident: $check:expr,)+) => {
        $(
            #[test]
            fn $test() {
                let check: fn(Backend, SolverConfig) = $check;
                if have_gpu() {
                    check($backend, $solver);
                }
            }
        )+
    };
}

/// The default soft-step solver on the checks that fit a software rasterizer's run time.
macro_rules! gpu_checks {
    ($name:ident, $backend:expr) => {
        checks!(
            $name,
            $backend,
            SolverConfig::default(),
            box_with_mu_half_sticks_on_a_20_degree_ramp: stability::ramp_box_sticks,
            box_with_mu_0_2_slides_at_coulombs_rate: stability::ramp_box_slides,
            overlapping_boxes_separate_within_the_push_out_cap:
                stability::overlapping_boxes_separate,
            fast_cube_does_not_pass_a_thin_floor: stability::fast_box_does_not_tunnel,
            spinning_box_keeps_its_angular_momentum: stability::spinning_box_keeps_momentum,
            bad_bodies_are_rejected: bad_input::bad_bodies_are_rejected,
            bad_updates_are_rejected: bad_input::bad_updates_are_rejected,
            stale_handles_are_rejected: bad_input::stale_handles_are_rejected,
        );
    };
}

gpu_checks!(gpu, Backend::Gpu);
gpu_checks!(hybrid, Backend::Hybrid);

/// The thesis's Baumgarte solver (rigid rows, 60 passes) on the checks that need warm starting
/// to carry across steps: its rows do not absorb a cold point as the soft step does, so a
/// stack stands only when every point, including those whose feature ids flip on coincident
/// edges, inherits last step's impulse (the GPU carry's position fallback).
macro_rules! baumgarte_checks {
    ($name:ident, $backend:expr) => {
        checks!($name, $backend, SolverConfig::baumgarte());
    };
}

/// The 10x wider box with contacts at the stiffness cap, on the whole-GPU step only: the
/// kernels take the floor contacts' stiffness from the host's `SolverParams`, which must hold
/// it to the same cap as tumble-solver does (`Backend::Hybrid` solves on the CPU).
#[test]
fn gpu_box_10x_wider_stands_on_four_cubes_with_stiff_contacts() {
    if have_gpu() {
        stability::stiff_wide_box_stands(Backend::Gpu, SolverConfig::default());
    }
}

baumgarte_checks!(gpu_baumgarte, Backend::Gpu);
baumgarte_checks!(hybrid_baumgarte, Backend::Hybrid);
