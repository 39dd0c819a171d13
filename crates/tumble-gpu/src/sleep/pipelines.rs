//! The sleep stage's pipelines, taken from the kernel cache when a world turns sleep on (a
//! world with sleep off never builds them).

use crate::kernel::pipelines;

use super::islands::{CHECK_LABELS, HOOK_LABELS, JUMP_LABELS};
use super::kinematic::KINEMATIC_WAKE;
use super::plan_search::PLAN_SEARCH;
use super::rest::{FALL_ASLEEP, ISLAND_REST, UPDATE_REST};
use super::touch::TOUCH_SLEEPERS;
use super::wake::{WAKE_BODIES, WAKE_ISLANDS};

pipelines! {
    /// Every pipeline of the sleep stage.
    pub struct SleepPipelines {
        /// Islands of the bodies the host touched.
        wake_bodies: WAKE_BODIES,
        /// Flagged islands wake.
        wake_islands: WAKE_ISLANDS,
        /// Rest timers; each body its own island.
        update_rest: UPDATE_REST,
        /// Sleeping islands reached, kinematic contacts.
        touch_sleepers: TOUCH_SLEEPERS,
        /// Sleeping islands a moving kinematic body's AABB reaches.
        kinematic_wake: KINEMATIC_WAKE,
        /// The search's dispatch sizes.
        plan_search: PLAN_SEARCH,
        /// One round's hooks.
        hook_labels: HOOK_LABELS,
        /// One round's pointer jumps.
        jump_labels: JUMP_LABELS,
        /// The unfinished-search flag.
        check_labels: CHECK_LABELS,
        /// Each island's shortest rest time.
        island_rest: ISLAND_REST,
        /// Islands that rested long enough leave the step.
        fall_asleep: FALL_ASLEEP,
    }
}
