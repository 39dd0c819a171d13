//! The `color` stage on the GPU. `color_propose` and `color_resolve` run the first (seeded)
//! round with one thread per constraint; `color_withdraw` withdraws its claims and lists the
//! constraints still undecided; `color_finish` runs the remaining rounds over that list in
//! one workgroup; `color_count` counts the colors and lays out the sort keys, one thread per
//! constraint again; `color_plan` writes the per-color offsets and dispatch sizes; a stable
//! radix sort by color then gives the constraint order. Only the rounds after the first run
//! in a single workgroup, over the few constraints the seeded first round left undecided.
//! The CPU twin is `tumble_solver::color_in_rounds` (re-exported here), the same rounds on
//! the host.

use crate::kernel::KernelSpec;
use crate::shader::file;

use super::pipelines::SolverPipelines;

/// Kernel: round 0 proposals, one thread per constraint.
pub static COLOR_PROPOSE: KernelSpec = KernelSpec::new(file("solver/color_propose.wgsl"));

/// Kernel: round 0 decisions, one thread per constraint.
pub static COLOR_RESOLVE: KernelSpec = KernelSpec::new(file("solver/color_resolve.wgsl"));

/// Kernel: withdraws round 0's claims and lists the undecided constraints, one thread per
/// constraint.
pub static COLOR_WITHDRAW: KernelSpec = KernelSpec::new(file("solver/color_withdraw.wgsl"));

/// Kernel: the remaining rounds over the undecided list (one workgroup).
pub static COLOR_FINISH: KernelSpec = KernelSpec::new(file("solver/color_finish.wgsl"));

/// Kernel: each world's first manifold, one thread per manifold (steps of several worlds).
pub static WORLD_STARTS: KernelSpec = KernelSpec::new(file("solver/world_starts.wgsl"));

/// Kernel: per-color counts and sort keys, one thread per constraint.
pub static COLOR_COUNT: KernelSpec = KernelSpec::new(file("solver/color_count.wgsl"));

/// Kernel: color offsets and per-color dispatch sizes (one thread).
pub static COLOR_PLAN: KernelSpec = KernelSpec::new(file("solver/color_plan.wgsl"));

/// The color stage's bind groups for one parity, in the order [`Self::record`] runs them.
#[derive(Debug)]
pub(super) struct ColorGroups {
    world_starts: wgpu::BindGroup,
    propose: wgpu::BindGroup,
    resolve: wgpu::BindGroup,
    withdraw: wgpu::BindGroup,
    finish: wgpu::BindGroup,
    count: wgpu::BindGroup,
    plan: wgpu::BindGroup,
}

impl ColorGroups {
    /// The bind groups over `buffer`'s buffers, by binding name.
    pub(super) fn new<'a>(
        ctx: &crate::GpuContext,
        k: &SolverPipelines,
        buffer: impl Fn(&'static str) -> &'a wgpu::Buffer,
    ) -> Self {
        Self {
            world_starts: k.world_starts.bind_named(ctx, &buffer),
            propose: k.color_propose.bind_named(ctx, &buffer),
            resolve: k.color_resolve.bind_named(ctx, &buffer),
            withdraw: k.color_withdraw.bind_named(ctx, &buffer),
            finish: k.color_finish.bind_named(ctx, &buffer),
            count: k.color_count.bind_named(ctx, &buffer),
            plan: k.color_plan.bind_named(ctx, &buffer),
        }
    }

    /// Records `world_starts` alone: each world's manifold range, for `solve_worlds`. The
    /// range buffers must be zero.
    pub(super) fn record_world_starts(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        k: &SolverPipelines,
        work: &wgpu::Buffer,
    ) {
        k.world_starts.dispatch_work(pass, &self.world_starts, work);
    }

    /// Records the stage up to the sort keys and dispatch sizes; the per-constraint kernels
    /// read their size from `work` on the GPU. The tally and the claims must be zero. With
    /// more than one world in the step, each world's first manifold is found first.
    pub(super) fn record(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        k: &SolverPipelines,
        work: &wgpu::Buffer,
        worlds: u32,
    ) {
        if worlds > 1 {
            k.world_starts.dispatch_work(pass, &self.world_starts, work);
        }
        k.color_propose.dispatch_work(pass, &self.propose, work);
        k.color_resolve.dispatch_work(pass, &self.resolve, work);
        k.color_withdraw.dispatch_work(pass, &self.withdraw, work);
        k.color_finish.dispatch_workgroups(pass, &self.finish, 1, 1);
        k.color_count.dispatch_work(pass, &self.count, work);
        k.color_plan.dispatch_workgroups(pass, &self.plan, 1, 1);
    }
}

pub use tumble_solver::{ColorCandidate, color_in_rounds, color_priority, hash_u32};
