//! The solver's pipelines for one set of effects, taken from the kernel cache
//! ([`Kernel::specialized`]): each kernel gets the effect switches it declares, so a set of
//! effects that only differs in a switch a kernel lacks reuses that kernel's pipeline.

use crate::kernel::{Kernel, KernelSpec, pipelines};
use crate::{GpuContext, GpuError};

use super::apply_impulses::APPLY_IMPULSES;
use super::color::{
    COLOR_COUNT, COLOR_FINISH, COLOR_PLAN, COLOR_PROPOSE, COLOR_RESOLVE, COLOR_WITHDRAW,
    WORLD_STARTS,
};
use super::effects::{Effects, effect_overrides};
use super::fused::{
    SOLVE_FUSED, SOLVE_FUSED_SHARED, SOLVE_WORLDS, SOLVE_WORLDS_SHARED, WORLDS_OVERRIDES,
    WORLDS_SHARED_OVERRIDES,
};
use super::integrate::{FINALIZE_BODIES, INTEGRATE_POSITIONS, INTEGRATE_VELOCITIES};
use super::prepare::{PREPARE_BODIES, PREPARE_CONTACTS, WARM_START_BODIES};
use super::solve_color::{PassKind, solve_color_spec};
use super::solve_step::SOLVE_STEP;
use super::store::STORE_IMPULSES;

pipelines! {
    /// The solver's kernels of one specialization each, for one set of effects.
    pub struct SolverPipelines {
        /// Each world's first manifold (steps of several worlds).
        world_starts: WORLD_STARTS,
        /// Round 0 proposals.
        color_propose: COLOR_PROPOSE,
        /// Round 0 decisions.
        color_resolve: COLOR_RESOLVE,
        /// Round 0's claims withdrawn, the undecided listed.
        color_withdraw: COLOR_WITHDRAW,
        /// Remaining rounds over the undecided (one workgroup).
        color_finish: COLOR_FINISH,
        /// Per-color counts and sort keys.
        color_count: COLOR_COUNT,
        /// Color offsets and dispatch sizes.
        color_plan: COLOR_PLAN,
        /// Deltas reset, world masses.
        prepare_bodies: PREPARE_BODIES,
        /// Constraints from manifolds.
        prepare_contacts: PREPARE_CONTACTS,
        /// The graph colors' warm start, one thread per body.
        warm_start_bodies: WARM_START_BODIES,
        /// Velocities by one substep.
        integrate_velocities: INTEGRATE_VELOCITIES,
        /// Deltas by one substep.
        integrate_positions: INTEGRATE_POSITIONS,
        /// Deltas into poses.
        finalize_bodies: FINALIZE_BODIES,
        /// Impulses back into contacts.
        store_impulses: STORE_IMPULSES,
        /// The whole color and solve stage in one workgroup.
        solve_fused: SOLVE_FUSED,
        /// The same with the bodies in workgroup memory.
        solve_fused_shared: SOLVE_FUSED_SHARED,
        /// The same, one workgroup per group of worlds of a batch.
        solve_worlds: SOLVE_WORLDS,
        /// The same with each group's bodies in workgroup memory.
        solve_worlds_shared: SOLVE_WORLDS_SHARED,
        /// Impulses queued by the host.
        apply_impulses: APPLY_IMPULSES,
    }
}

/// `spec`'s pipeline with the effect switches it declares and `extra`.
fn with_effects(
    ctx: &GpuContext,
    effects: &Effects,
    spec: &'static KernelSpec,
    extra: &[(&'static str, f64)],
) -> Result<Kernel, GpuError> {
    let mut values = spec.declared(&effect_overrides(effects))?;
    values.extend_from_slice(extra);
    Kernel::specialized(ctx, spec, &values)
}

impl SolverPipelines {
    /// Every pipeline for `effects`, built on first use on this device and shared after.
    pub fn new(ctx: &GpuContext, effects: &Effects) -> Result<Self, GpuError> {
        Self::build(|spec| {
            let extra: &[(&'static str, f64)] = if std::ptr::eq(spec, &SOLVE_WORLDS) {
                &WORLDS_OVERRIDES
            } else if std::ptr::eq(spec, &SOLVE_WORLDS_SHARED) {
                &WORLDS_SHARED_OVERRIDES
            } else {
                &[]
            };
            with_effects(ctx, effects, spec, extra)
        })
    }
}

/// The per-color pass kernels for `effects`, one per [`PassKind`] in [`PassKind::ALL`] order:
/// `solve_color_immediate` on a device with immediate data, `solve_color` elsewhere.
pub fn pass_kernels(ctx: &GpuContext, effects: &Effects) -> Result<Vec<Kernel>, GpuError> {
    PassKind::ALL
        .iter()
        .map(|pass| {
            with_effects(
                ctx,
                effects,
                solve_color_spec(ctx.has_immediates),
                &[("PASS", f64::from(pass.code()))],
            )
        })
        .collect()
}

/// `solve_step` for `effects` on a device with `@coherent` storage when `wanted`, `None`
/// otherwise (the wide path then dispatches its substeps per color). Built only where a step
/// may use it: a CPU adapter defaults to the per-color dispatches and would compile it for
/// nothing.
pub fn solve_step_kernel(
    ctx: &GpuContext,
    effects: &Effects,
    wanted: bool,
) -> Result<Option<Kernel>, GpuError> {
    if !(wanted && ctx.has_coherent) {
        return Ok(None);
    }
    let per_thread = ctx.info.device_type == wgpu::DeviceType::Cpu;
    with_effects(
        ctx,
        effects,
        &SOLVE_STEP,
        &[(
            "SOLVE_STEP_PER_THREAD_SYNC",
            f64::from(u8::from(per_thread)),
        )],
    )
    .map(Some)
}
