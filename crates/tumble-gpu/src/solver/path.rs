//! Which of the two solver paths runs a step: the wide path (one dispatch per color and pass,
//! every thread of the GPU) or the fused path (one workgroup, one dispatch). Both compute the
//! same result; the choice is only about speed.

use tumble_solver::SolverConfig;

use super::constants::COLOR_SLOTS;

/// The fused path is used up to this many manifolds. One workgroup visits a color in
/// batches of `WORKGROUP_SIZE` constraints, so its cost grows with the manifold count, while
/// the wide path pays a nearly fixed cost per dispatch (about 80 per substep). Measured on an
/// H100 (Vulkan, `benches/benches/gpu_step.rs`, docs/gpu-solver.md): the solver stages take
/// 6.0 ms fused against 6.7 ms wide at 4,324 manifolds and 27.7 ms against 7.8 ms at 20,540,
/// so the two cross near 4,500 (the wide path's extra recording time moves the wall-clock
/// crossover a little higher).
pub const FUSED_MAX_CONSTRAINTS: u32 = 4096;

/// The fused path is used up to this many bodies: its per-body stages also run in one
/// workgroup, `WORKGROUP_SIZE` bodies at a time (a pile at the manifold bound above has
/// about 600 bodies, so this bound only matters for sparse scenes).
pub const FUSED_MAX_BODIES: u32 = 4096;

/// How the color and solve stages are dispatched.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SolvePath {
    /// One dispatch per stage, color and pass, each as wide as its work.
    Wide,
    /// One single-workgroup dispatch for the whole color and solve stages.
    Fused,
}

impl SolvePath {
    /// The path for a step with `bodies` bodies and about `constraints` manifolds.
    pub fn choose(bodies: u32, constraints: u32) -> Self {
        if bodies <= FUSED_MAX_BODIES && constraints <= FUSED_MAX_CONSTRAINTS {
            SolvePath::Fused
        } else {
            SolvePath::Wide
        }
    }

    /// Compute dispatches this path records per step with `config` (restitution pass when
    /// `restitution`), not counting buffer clears and copies.
    pub fn dispatches_per_step(self, config: &SolverConfig, restitution: bool) -> u32 {
        match self {
            SolvePath::Fused => 1,
            SolvePath::Wide => {
                // propose, resolve, finish; two radix passes of three kernels.
                let color = 3 + 2 * 3;
                let prepare = 2;
                let sweeps = 1 + config.iterations + config.relax_iterations;
                let substep = 2 + COLOR_SLOTS * sweeps;
                let restitution = if restitution { COLOR_SLOTS } else { 0 };
                let finish = 2;
                color + prepare + config.substeps.max(1) * substep + restitution + finish
            }
        }
    }
}
