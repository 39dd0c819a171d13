//! The CPU stability suite: stacks, pyramids, mass ratios, friction, overlap recovery,
//! tunneling, gyroscopic motion, round-off far from the origin, finiteness and bad input, for
//! the default soft-step solver and for the thesis's Baumgarte solver.

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
