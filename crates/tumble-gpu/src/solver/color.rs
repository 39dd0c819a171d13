//! The `color` stage on the GPU. `color_propose` and `color_resolve` run the first (seeded)
//! round with one thread per constraint; `color_withdraw` withdraws its claims and lists the
//! constraints still undecided; `color_finish` runs the remaining rounds over that list in
//! one workgroup; `color_count` counts the colors and lays out the sort keys, one thread per
//! constraint again; `color_plan` writes the per-color offsets and dispatch sizes; a stable
//! radix sort by color then gives the constraint order. Only the rounds after the first run
//! in a single workgroup, over the few constraints the seeded first round left undecided.
//! The CPU twin is `tumble_solver::color_in_rounds` (re-exported here), the same rounds on
//! the host.

use crate::kernel::kernel;

use super::pipelines::SolverPipelines;

kernel! {
    /// Buffers of the kernels that run coloring rounds: [`COLOR_PROPOSE`], [`COLOR_RESOLVE`],
    /// [`COLOR_WITHDRAW`] and [`COLOR_FINISH`] (the first two leave the list and tally alone).
    pub struct ColorRoundArgs {
        /// `SolverParams` (for the body count).
        params,
        /// The contacts' `WorkList`.
        contact_work,
        /// `array<GpuManifold>`.
        manifolds,
        /// `array<GpuBody>`.
        bodies,
        /// Last step's `array<ColorSlot>`.
        previous_colors,
        /// This step's `array<ColorSlot>`.
        color_state,
        /// Used-color masks then claims, `u32`.
        color_marks,
        /// Two lists of undecided constraints, `2 * capacity` `u32`.
        color_scratch,
        /// The tally, `COLOR_TALLY_LEN` `u32` (zeroed before the stage).
        color_tally,
    }
    /// Kernel: round 0 proposals, one thread per constraint.
    pub static COLOR_PROPOSE = "solver/color_propose.wgsl";
    /// Kernel: round 0 decisions, one thread per constraint.
    pub static COLOR_RESOLVE = "solver/color_resolve.wgsl";
    /// Kernel: withdraws round 0's claims and lists the undecided constraints, one thread per
    /// constraint.
    pub static COLOR_WITHDRAW = "solver/color_withdraw.wgsl";
    /// Kernel: the remaining rounds over the undecided list (one workgroup).
    pub static COLOR_FINISH = "solver/color_finish.wgsl";
}

kernel! {
    /// Buffers of [`COLOR_COUNT`].
    pub struct ColorCountArgs {
        /// The contacts' `WorkList`.
        contact_work,
        /// This step's `array<ColorSlot>`, every color decided.
        color_state,
        /// The tally, whose per-color counts this adds to.
        color_tally,
        /// Output: sort keys (the colors).
        sort_keys,
        /// Output: sort values (the constraint indices).
        sort_values,
    }
    /// Kernel: per-color counts and sort keys, one thread per constraint.
    pub static COLOR_COUNT = "solver/color_count.wgsl";
}

kernel! {
    /// Buffers of [`COLOR_PLAN`].
    pub struct ColorPlanArgs {
        /// The tally with every color counted.
        color_tally,
        /// Output: `COLOR_OFFSETS_LEN` offsets.
        color_offsets,
        /// Output: `array<DispatchArgs>`, one per color slot.
        color_args,
    }
    /// Kernel: color offsets and per-color dispatch sizes (one thread).
    pub static COLOR_PLAN = "solver/color_plan.wgsl";
}

/// The color stage's bind groups for one parity, in the order [`Self::record`] runs them.
#[derive(Debug)]
pub(super) struct ColorGroups {
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
            propose: k.color_propose.bind_named(ctx, &buffer),
            resolve: k.color_resolve.bind_named(ctx, &buffer),
            withdraw: k.color_withdraw.bind_named(ctx, &buffer),
            finish: k.color_finish.bind_named(ctx, &buffer),
            count: k.color_count.bind_named(ctx, &buffer),
            plan: k.color_plan.bind_named(ctx, &buffer),
        }
    }

    /// Records the stage up to the sort keys and dispatch sizes; the per-constraint kernels
    /// read their size from `work` on the GPU. The tally and the claims must be zero.
    pub(super) fn record(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        k: &SolverPipelines,
        work: &wgpu::Buffer,
    ) {
        k.color_propose.dispatch_work(pass, &self.propose, work);
        k.color_resolve.dispatch_work(pass, &self.resolve, work);
        k.color_withdraw.dispatch_work(pass, &self.withdraw, work);
        k.color_finish.dispatch_workgroups(pass, &self.finish, 1, 1);
        k.color_count.dispatch_work(pass, &self.count, work);
        k.color_plan.dispatch_workgroups(pass, &self.plan, 1, 1);
    }
}

pub use tumble_solver::{ColorCandidate, color_in_rounds, color_priority, hash_u32};
