//! The bind groups of every solver kernel over one set of step buffers: built again only
//! when the buffers change (`GpuSolver::rebind`).

use super::*;

impl GpuSolver {
    pub(super) fn make_bind_groups(&self, inputs: &StepBuffers<'_>) -> BindGroups {
        let ctx = &self.ctx;
        let k = &self.pipelines;
        let get = |name| self.pool.get(name);
        let order = get(SORT_VALUES[result_copy(&self.sort_passes)]);
        // Every kernel's buffers by binding name: the step's, then the pool's (named as the
        // bindings are). `p` is the parity: which copy of the colors and tilts is this step's.
        let buffer = |p: usize| {
            move |name: &'static str| match name {
                "params" => &self.params,
                "contact_work" => inputs.contact_work,
                "manifolds" => inputs.manifolds,
                "contacts" => inputs.contacts,
                "bodies" => inputs.bodies,
                "poses" => inputs.poses,
                "velocities" | "velocity_buffer" => inputs.velocities,
                "solver_body_buffer" => get(SOLVER_BODIES),
                "previous_colors" => get(COLOR_STATE[1 - p]),
                "color_state" => get(COLOR_STATE[p]),
                "previous_tilts" => get(TILTS[1 - p]),
                "tilts" => get(TILTS[p]),
                "sort_keys" => get(SORT_KEYS[0]),
                "sort_values" => get(SORT_VALUES[0]),
                "color_order" => order,
                name => get(name),
            }
        };
        let both = |kernel: &Kernel| [0, 1].map(|p| kernel.bind_named(ctx, buffer(p)));
        let radix = self.radix.bind(
            ctx,
            &RadixBuffers {
                work: inputs.contact_work,
                first: [get(SORT_KEYS[0]), get(SORT_KEYS[1])],
                second: [get(SORT_VALUES[0]), get(SORT_VALUES[1])],
                tile_counts: get(SORT_TILES),
            },
            &self.sort_passes,
        );
        let passes = PassKind::ALL
            .iter()
            .map(|&kind| {
                let kernel = &self.passes[kind.index()];
                if self.ctx.has_immediates {
                    return PassGroups::Immediate(kernel.bind_named(ctx, buffer(0)));
                }
                let pass = |pass_color| {
                    kernel.bind_named(ctx, |name| match name {
                        "pass_color" => pass_color,
                        name => buffer(0)(name),
                    })
                };
                PassGroups::Uniform(self.pass_colors.iter().map(pass).collect())
            })
            .collect();
        BindGroups {
            color: [0, 1].map(|p| ColorGroups::new(ctx, k, buffer(p))),
            radix,
            prepare_bodies: k.prepare_bodies.bind_named(ctx, buffer(0)),
            prepare_contacts: both(&k.prepare_contacts),
            warm_start_bodies: k.warm_start_bodies.bind_named(ctx, buffer(0)),
            integrate_velocities: k.integrate_velocities.bind_named(ctx, buffer(0)),
            integrate_positions: k.integrate_positions.bind_named(ctx, buffer(0)),
            finalize_bodies: k.finalize_bodies.bind_named(ctx, buffer(0)),
            store_impulses: both(&k.store_impulses),
            passes,
            solve_fused: both(&k.solve_fused),
            solve_fused_shared: both(&k.solve_fused_shared),
            solve_worlds: both(&k.solve_worlds),
            solve_worlds_shared: both(&k.solve_worlds_shared),
            solve_step: self
                .solve_step
                .as_ref()
                .map(|kernel| kernel.bind_named(ctx, buffer(0))),
        }
    }
}
