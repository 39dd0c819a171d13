//! The sleep stage's pipelines, built once per device on the first world that turns sleep on,
//! and shared after (a world with sleep off never builds them).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use crate::kernel::Kernel;
use crate::{GpuContext, GpuError};

use super::islands::{CHECK_LABELS, HOOK_LABELS, JUMP_LABELS};
use super::kinematic::KINEMATIC_WAKE;
use super::plan_search::PLAN_SEARCH;
use super::rest::{FALL_ASLEEP, ISLAND_REST, UPDATE_REST};
use super::shaders::build_sleep_kernel;
use super::touch::TOUCH_SLEEPERS;
use super::wake::{WAKE_BODIES, WAKE_ISLANDS};

/// Every pipeline of the sleep stage.
#[derive(Debug)]
pub struct SleepPipelines {
    /// Islands of the bodies the host touched.
    pub wake_bodies: Kernel,
    /// Flagged islands wake.
    pub wake_islands: Kernel,
    /// Rest timers; each body its own island.
    pub update_rest: Kernel,
    /// Sleeping islands reached, kinematic contacts.
    pub touch_sleepers: Kernel,
    /// Sleeping islands a moving kinematic body's AABB reaches.
    pub kinematic_wake: Kernel,
    /// The search's dispatch sizes.
    pub plan_search: Kernel,
    /// One round's hooks.
    pub hook_labels: Kernel,
    /// One round's pointer jumps.
    pub jump_labels: Kernel,
    /// The unfinished-search flag.
    pub check_labels: Kernel,
    /// Each island's shortest rest time.
    pub island_rest: Kernel,
    /// Islands that rested long enough leave the step.
    pub fall_asleep: Kernel,
}

type Cache = Mutex<HashMap<wgpu::Device, Arc<SleepPipelines>>>;

impl SleepPipelines {
    /// Builds every pipeline.
    pub fn new(ctx: &GpuContext) -> Result<Self, GpuError> {
        let build = |spec| build_sleep_kernel(ctx, spec);
        Ok(Self {
            wake_bodies: build(&WAKE_BODIES)?,
            wake_islands: build(&WAKE_ISLANDS)?,
            update_rest: build(&UPDATE_REST)?,
            touch_sleepers: build(&TOUCH_SLEEPERS)?,
            kinematic_wake: build(&KINEMATIC_WAKE)?,
            plan_search: build(&PLAN_SEARCH)?,
            hook_labels: build(&HOOK_LABELS)?,
            jump_labels: build(&JUMP_LABELS)?,
            check_labels: build(&CHECK_LABELS)?,
            island_rest: build(&ISLAND_REST)?,
            fall_asleep: build(&FALL_ASLEEP)?,
        })
    }

    /// The pipelines on `ctx`'s device, built on first use and shared after.
    pub fn shared(ctx: &GpuContext) -> Result<Arc<Self>, GpuError> {
        static CACHE: OnceLock<Cache> = OnceLock::new();
        let cache = CACHE.get_or_init(Default::default);
        if let Some(found) = cache.lock().expect("pipeline cache lock").get(&ctx.device) {
            return Ok(found.clone());
        }
        // Built outside the lock: another thread building them too only wastes time.
        let built = Arc::new(Self::new(ctx)?);
        Ok(cache
            .lock()
            .expect("pipeline cache lock")
            .entry(ctx.device.clone())
            .or_insert(built)
            .clone())
    }
}
