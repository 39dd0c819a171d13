//! Every solver pipeline, built once per device and set of effects and shared (pipeline
//! creation is the slow part of starting a GPU world: on a software rasterizer the fused
//! kernel alone takes a large fraction of a second to compile).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use crate::kernel::Kernel;
use crate::kernels::radix_sort::RadixSort;
use crate::{GpuContext, GpuError};

use super::apply_impulses::APPLY_IMPULSES;
use super::color::{COLOR_FINISH, COLOR_PROPOSE, COLOR_RESOLVE};
use super::effects::Effects;
use super::fused::SOLVE_FUSED;
use super::integrate::{FINALIZE_BODIES, INTEGRATE_POSITIONS, INTEGRATE_VELOCITIES};
use super::prepare::{PREPARE_BODIES, PREPARE_CONTACTS};
use super::shaders::build_kernel;
use super::solve_color::{PassKind, SOLVE_COLOR};
use super::store::STORE_IMPULSES;

/// The solver's pipelines for one set of effects.
#[derive(Debug)]
pub struct SolverPipelines {
    /// The effects compiled in.
    pub effects: Effects,
    /// Round 0 proposals.
    pub color_propose: Kernel,
    /// Round 0 decisions.
    pub color_resolve: Kernel,
    /// Remaining rounds, counts, dispatch sizes.
    pub color_finish: Kernel,
    /// The stable sort by color.
    pub radix: RadixSort,
    /// Deltas reset, world masses.
    pub prepare_bodies: Kernel,
    /// Constraints from manifolds.
    pub prepare_contacts: Kernel,
    /// Velocities by one substep.
    pub integrate_velocities: Kernel,
    /// Deltas by one substep.
    pub integrate_positions: Kernel,
    /// Deltas into poses.
    pub finalize_bodies: Kernel,
    /// Impulses back into contacts.
    pub store_impulses: Kernel,
    /// One per [`PassKind`], in [`PassKind::ALL`] order.
    pub solve_color: Vec<Kernel>,
    /// The whole color and solve stage in one workgroup.
    pub solve_fused: Kernel,
    /// Impulses queued by the host.
    pub apply_impulses: Kernel,
}

type Cache = Mutex<HashMap<(wgpu::Device, Effects), Arc<SolverPipelines>>>;

impl SolverPipelines {
    /// Builds every pipeline for `effects`.
    pub fn new(ctx: &GpuContext, effects: Effects) -> Result<Self, GpuError> {
        let switches = effects.overrides();
        let build = |spec| build_kernel(ctx, spec, &switches);
        let solve_color = PassKind::ALL
            .iter()
            .map(|pass| {
                let mut extra = switches.to_vec();
                extra.push(("PASS", f64::from(pass.code())));
                build_kernel(ctx, &SOLVE_COLOR, &extra)
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            effects,
            color_propose: build(&COLOR_PROPOSE)?,
            color_resolve: build(&COLOR_RESOLVE)?,
            color_finish: build(&COLOR_FINISH)?,
            radix: RadixSort::new(ctx)?,
            prepare_bodies: build(&PREPARE_BODIES)?,
            prepare_contacts: build(&PREPARE_CONTACTS)?,
            integrate_velocities: build(&INTEGRATE_VELOCITIES)?,
            integrate_positions: build(&INTEGRATE_POSITIONS)?,
            finalize_bodies: build(&FINALIZE_BODIES)?,
            store_impulses: build(&STORE_IMPULSES)?,
            solve_color,
            solve_fused: build(&SOLVE_FUSED)?,
            apply_impulses: build(&APPLY_IMPULSES)?,
        })
    }

    /// The pipelines for `effects` on `ctx`'s device, built on first use and shared after.
    pub fn shared(ctx: &GpuContext, effects: Effects) -> Result<Arc<Self>, GpuError> {
        static CACHE: OnceLock<Cache> = OnceLock::new();
        let cache = CACHE.get_or_init(Default::default);
        let key = (ctx.device.clone(), effects);
        if let Some(found) = cache.lock().expect("pipeline cache lock").get(&key) {
            return Ok(found.clone());
        }
        // Built outside the lock: another thread building the same set only wastes time.
        let built = Arc::new(Self::new(ctx, effects)?);
        Ok(cache
            .lock()
            .expect("pipeline cache lock")
            .entry(key)
            .or_insert(built)
            .clone())
    }

    /// The per-color pass kernel of `pass`.
    pub fn pass(&self, pass: PassKind) -> &Kernel {
        &self.solve_color[pass.index()]
    }
}
