//! `plan_search`: the island search and the kernels after it are dispatched indirectly, with
//! zero workgroups in a step where no body has rested for `TIME_TO_SLEEP` (most steps of a
//! moving scene). The CPU twin is the early return of [`tumble_solver::SleepLabels::fall_asleep`].

use crate::kernel::kernel;
use crate::layout::DispatchArgs;

/// Byte offset in the search groups buffer of the dispatch over the step's manifolds.
pub const LINK_GROUPS_OFFSET: u64 = 0;
/// Byte offset in the search groups buffer of the dispatch over every body.
pub const BODY_GROUPS_OFFSET: u64 = std::mem::size_of::<DispatchArgs>() as u64;

kernel! {
    /// Buffers of [`PLAN_SEARCH`].
    pub struct PlanSearchArgs {
        /// `SleepParams`.
        params,
        /// The step's pair `WorkList`.
        work,
        /// One `u32`: bodies whose rest reached `TIME_TO_SLEEP`.
        ready,
        /// `array<DispatchArgs, 2>`: the manifold and every-body dispatches of the search.
        search_groups,
    }
    /// Kernel: a single thread.
    pub static PLAN_SEARCH = "sleep/plan_search.wgsl";
}
