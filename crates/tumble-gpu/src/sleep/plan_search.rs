//! `plan_search`: the island search and the kernels after it are dispatched indirectly, with
//! zero workgroups in a step where no body has rested for `TIME_TO_SLEEP` (most steps of a
//! moving scene). The CPU twin is the early return of [`super::cpu::SleepCpu::fall_asleep`].

use crate::kernel::{KernelArgs, KernelSpec};
use crate::layout::DispatchArgs;
use crate::shader::{Binding, ShaderSource, wgsl_file};

use super::shaders::SLEEP_COMMON;

/// Byte offset in the search groups buffer of the dispatch over the step's manifolds.
pub const LINK_GROUPS_OFFSET: u64 = 0;
/// Byte offset in the search groups buffer of the dispatch over every body.
pub const BODY_GROUPS_OFFSET: u64 = std::mem::size_of::<DispatchArgs>() as u64;

/// Kernel: a single thread.
pub static PLAN_SEARCH: KernelSpec = KernelSpec {
    name: "plan_search",
    source: ShaderSource {
        common: SLEEP_COMMON,
        kernel: wgsl_file!("sleep/plan_search.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`PLAN_SEARCH`].
pub struct PlanSearchArgs<'a> {
    /// `SleepParams`.
    pub params: &'a wgpu::Buffer,
    /// The step's pair `WorkList`.
    pub work: &'a wgpu::Buffer,
    /// One `u32`: bodies whose rest reached `TIME_TO_SLEEP`.
    pub ready: &'a wgpu::Buffer,
    /// `array<DispatchArgs, 2>`: the manifold and every-body dispatches of the search.
    pub search_groups: &'a wgpu::Buffer,
}

impl KernelArgs for PlanSearchArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![self.params, self.work, self.ready, self.search_groups]
    }
}
