//! The CPU stability suite: stacks, pyramids, mass ratios, friction, overlap recovery,
//! tunneling, gyroscopic motion, round-off far from the origin, every canonical scene against
//! its own check for its full length (`canonical_scenes_pass_their_checks`), and bad input,
//! for the default soft-step solver, for the soft step with friction in the relax passes only
//! (`FrictionPasses::RelaxOnly`) and for the thesis's Baumgarte solver.
//!
//! The canonical sweeps of the two soft-step suites take about 25 s of CPU time together with
//! the Baumgarte one, each soft step's 650-cube pyramid most of it (the Baumgarte sweep leaves
//! that pyramid to `pyramid_of_650_cubes_stands_10_s`, which runs the same scene with a
//! tighter bound).

tumble_tests::stability_suite!(
    soft_step,
    tumble::Backend::Cpu,
    tumble::SolverConfig::default()
);

tumble_tests::stability_suite!(
    baumgarte,
    tumble::Backend::Cpu,
    tumble::SolverConfig::baumgarte()
);

/// The 10x wider box with contacts at the stiffness cap (soft step only: the Baumgarte solver
/// has no contact stiffness).
#[test]
fn box_10x_wider_stands_on_four_cubes_with_stiff_contacts() {
    tumble_tests::stability::stiff_wide_box_stands(
        tumble::Backend::Cpu,
        tumble::SolverConfig::default(),
    );
}

/// The 4,901-cube pyramid, with the default soft step only: the thesis's Baumgarte solver at
/// 60 passes costs too much at this size for CI, and the 650-cube pyramid covers it.
#[test]
fn large_pyramid_of_4901_cubes_stands_2_s() {
    tumble_tests::stability::large_pyramid_stands(
        tumble::Backend::Cpu,
        tumble::SolverConfig::default(),
    );
}

// Friction in the relax passes only (rapier3d's default): the biased passes solve
// the normal and tilt rows alone, so the same suite checks that stacks, pyramids, ramps and
// the canonical scenes still hold with friction and the patches' second visit left to the
// relax passes.
tumble_tests::stability_suite!(
    soft_step_relax_only_friction,
    tumble::Backend::Cpu,
    tumble::SolverConfig {
        friction_passes: tumble::FrictionPasses::RelaxOnly,
        ..tumble::SolverConfig::default()
    }
);
