//! The step-wide solver values, computed on the host from a `SolverConfig` exactly as
//! tumble-solver's `solve` computes them, for the GPU (`SolverParams`) and for the CPU twins
//! (`PrepareContext`).

use tumble_geometry::{Real, Vec3};
use tumble_solver::{FrictionPasses, PrepareContext, Softness, SolverConfig, SolverKind};

use super::layout::SolverParams;

/// One step's solver values in both forms.
#[derive(Clone, Copy, Debug)]
pub struct StepParams {
    /// The uniform block of the GPU kernels.
    pub params: SolverParams,
    /// The same values as tumble-solver's `prepare_contact` takes them.
    pub prepare: PrepareContext,
}

fn softness_vec(s: &Softness) -> [f32; 4] {
    [s.bias_rate, s.mass_scale, s.impulse_scale, 0.0]
}

impl StepParams {
    /// The values of a step of length `dt` under `gravity` with `body_count` bodies;
    /// `restitution` says whether some material bounces (the restitution pass runs).
    pub fn new(
        config: &SolverConfig,
        dt: Real,
        gravity: &Vec3,
        body_count: u32,
        restitution: bool,
    ) -> Self {
        let substeps = config.substeps.max(1);
        let h = dt / substeps as Real;
        let inv_h = 1.0 / h;
        let (contact_softness, static_softness) = config.softness(h);
        let slop = match config.kind {
            SolverKind::Baumgarte => config.slop,
            SolverKind::SoftStep => 0.0,
        };
        let warm_start_scale = if config.warm_start { 1.0 } else { 0.0 };
        let params = SolverParams {
            gravity: [gravity.x, gravity.y, gravity.z, 0.0],
            contact_softness: softness_vec(&contact_softness),
            static_softness: softness_vec(&static_softness),
            h,
            inv_h,
            max_push_out: config.max_push_out,
            restitution_threshold: config.restitution_threshold,
            slop,
            warm_start_scale,
            body_count,
            substeps,
            iterations: config.iterations,
            relax_iterations: config.relax_iterations,
            restitution: u32::from(restitution),
            relax_only_friction: u32::from(config.friction_passes == FrictionPasses::RelaxOnly),
        };
        let prepare = PrepareContext {
            kind: config.kind,
            h,
            contact_softness,
            static_softness,
            slop: config.slop,
            warm_start_scale,
        };
        Self { params, prepare }
    }
}
