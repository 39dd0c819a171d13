//! `plan_search`: the island search and the kernels after it are dispatched indirectly, with
//! zero workgroups in a step where no body has rested for `TIME_TO_SLEEP` (most steps of a
//! moving scene). The CPU twin is the early return of [`tumble_solver::SleepLabels::fall_asleep`].

use crate::kernel::KernelSpec;
use crate::layout::DispatchArgs;
use crate::shader::file;

/// Byte offset in the search groups buffer of the dispatch over the step's manifolds.
pub const LINK_GROUPS_OFFSET: u64 = 0;
/// Byte offset in the search groups buffer of the dispatch over every body.
pub const BODY_GROUPS_OFFSET: u64 = std::mem::size_of::<DispatchArgs>() as u64;

/// Kernel: a single thread.
pub static PLAN_SEARCH: KernelSpec = KernelSpec::new(file("sleep/plan_search.wgsl"));
