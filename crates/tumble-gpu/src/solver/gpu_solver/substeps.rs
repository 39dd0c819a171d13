//! The wide path's substeps: every substep in one `solve_step` dispatch, or per color (one
//! dispatch per graph color and pass), the same bits either way; and how the step picks
//! between the two ([`SubstepDispatch`]).

use super::*;

impl GpuSolver {
    /// How the wide path dispatches its substeps from the next step on ([`SubstepDispatch`];
    /// the same bits either way). Builds `solve_step` if it was not built yet and may now run;
    /// errs, changing nothing, on a forced workgroup count outside 1 to 65,535.
    pub fn set_substep_dispatch(&mut self, dispatch: SubstepDispatch) -> Result<(), GpuError> {
        dispatch.validate("substep_dispatch")?;
        if self.solve_step.is_none() && dispatch.may_use_one_dispatch(self.ctx.info.device_type) {
            self.solve_step = solve_step_kernel(&self.ctx, &self.effects, true)?;
            // The bind groups were made without it.
            self.bind.clear();
        }
        self.substep_dispatch = dispatch;
        Ok(())
    }

    /// How the wide path dispatches its substeps ([`Self::set_substep_dispatch`]).
    pub fn substep_dispatch(&self) -> SubstepDispatch {
        self.substep_dispatch
    }

    /// The workgroups of the wide path's one substep dispatch for a step of `bodies` bodies, or
    /// `None` when it dispatches per color ([`SubstepDispatch::one_dispatch_groups`]). The
    /// one dispatch warms per body, so a step whose warm start goes by color
    /// ([`Self::set_warm_start_sweep`]) dispatches per color.
    pub fn substep_groups(&self, bodies: u32) -> Option<u32> {
        if !self.warm_start.per_body(self.ctx.info.device_type) {
            return None;
        }
        self.substep_dispatch.one_dispatch_groups(
            bodies,
            self.ctx.info.device_type,
            self.solve_step.is_some(),
        )
    }

    /// The fault word of the last recorded step's one substep dispatch (a `u32` at the byte
    /// offset, set when one of its waits gave up and the step's results may be wrong), when
    /// that step ran its substeps in one dispatch.
    pub fn substep_fault(&self) -> Option<(&wgpu::Buffer, u64)> {
        self.last_one_dispatch.then(|| {
            (
                self.pool.get(STEP_PROGRESS),
                2 * std::mem::size_of::<u32>() as u64,
            )
        })
    }

    /// Records the wide path's substeps after its coloring and prepare: one `solve_step`
    /// dispatch where [`Self::substep_groups`] gives it workgroups, else per color. Returns
    /// whether it took the one dispatch.
    pub(super) fn record_substeps(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut StageTimer,
        groups: &BindGroups,
        n: u32,
        params: &SolverParams,
    ) -> bool {
        let k = &self.pipelines;
        let args = self.pool.get(COLOR_ARGS);
        let sweep = |pass: &mut wgpu::ComputePass<'_>, kind: PassKind| {
            groups.passes[kind.index()].sweep(
                pass,
                &self.passes[kind.index()],
                args,
                self.color_dispatches,
            );
        };
        if let (Some(groups_x), Some(kernel), Some(group)) =
            (self.substep_groups(n), &self.solve_step, &groups.solve_step)
        {
            // Every substep in one dispatch: the phases of the per-color dispatches
            // below, in the same order.
            encoder.clear_buffer(self.pool.get(STEP_PROGRESS), 0, None);
            let mut pass = timer.begin_pass(encoder, "solve");
            kernel.dispatch_workgroups(&mut pass, group, groups_x, 1);
            true
        } else {
            for substep in 0..params.substeps {
                // The GPU runs what is recorded so far while the host records the next
                // substep's ~50 dispatches (about 0.25 ms of host time each substep).
                submit_so_far(&self.ctx, encoder);
                let mut pass = timer.begin_pass(encoder, "solve");
                k.integrate_velocities
                    .dispatch(&mut pass, &groups.integrate_velocities, n);
                if self.warm_start.per_body(self.ctx.info.device_type) {
                    k.warm_start_bodies
                        .dispatch(&mut pass, &groups.warm_start_bodies, n);
                    // The overflow set after every color, in one thread, as in the
                    // colored sweep.
                    let warm = PassKind::WarmStart.index();
                    groups.passes[warm].overflow(&mut pass, &self.passes[warm]);
                } else {
                    sweep(&mut pass, PassKind::WarmStart);
                }
                for _ in 0..params.iterations {
                    sweep(&mut pass, PassKind::Solve);
                }
                k.integrate_positions
                    .dispatch(&mut pass, &groups.integrate_positions, n);
                for _ in 0..params.relax_iterations {
                    sweep(&mut pass, PassKind::Relax);
                }
                if substep + 1 == params.substeps && params.restitution != 0 {
                    sweep(&mut pass, PassKind::Restitution);
                }
            }
            false
        }
    }
}
