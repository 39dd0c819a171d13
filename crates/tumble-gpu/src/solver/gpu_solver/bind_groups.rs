//! The bind groups of every solver kernel over one set of step buffers: built again only
//! when the buffers change (`GpuSolver::rebind`).

use super::*;

impl GpuSolver {
    pub(super) fn make_bind_groups(&self, inputs: &StepBuffers<'_>) -> BindGroups {
        let ctx = &self.ctx;
        let k = &self.pipelines;
        let get = |name| self.pool.get(name);
        let order = get(SORT_VALUES[result_copy(&self.sort_passes)]);
        let round = |p: usize| ColorRoundArgs {
            params: &self.params,
            contact_work: inputs.contact_work,
            manifolds: inputs.manifolds,
            bodies: inputs.bodies,
            previous_colors: get(COLOR_STATE[1 - p]),
            color_state: get(COLOR_STATE[p]),
            color_marks: get(COLOR_MARKS),
            color_scratch: get(COLOR_SCRATCH),
            color_tally: get(COLOR_TALLY),
        };
        let both = |f: &dyn Fn(usize) -> wgpu::BindGroup| [f(0), f(1)];
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
                self.pass_colors
                    .iter()
                    .map(|pass_color| {
                        self.passes[kind.index()].bind(
                            ctx,
                            &SolveColorArgs {
                                params: &self.params,
                                pass_color,
                                color_offsets: get(COLOR_OFFSETS),
                                solver_bodies: get(SOLVER_BODIES),
                                velocities: inputs.velocities,
                                constraints: get(CONSTRAINTS),
                            },
                        )
                    })
                    .collect()
            })
            .collect();
        BindGroups {
            color: [0, 1].map(|p| {
                ColorGroups::new(
                    ctx,
                    k,
                    &ColorBuffers {
                        rounds: round(p),
                        color_offsets: get(COLOR_OFFSETS),
                        color_args: get(COLOR_ARGS),
                        sort_keys: get(SORT_KEYS[0]),
                        sort_values: get(SORT_VALUES[0]),
                    },
                )
            }),
            radix,
            prepare_bodies: k.prepare_bodies.bind(
                ctx,
                &PrepareBodiesArgs {
                    params: &self.params,
                    bodies: inputs.bodies,
                    poses: inputs.poses,
                    solver_bodies: get(SOLVER_BODIES),
                },
            ),
            prepare_contacts: both(&|p| {
                k.prepare_contacts.bind(
                    ctx,
                    &PrepareContactsArgs {
                        params: &self.params,
                        contact_work: inputs.contact_work,
                        manifolds: inputs.manifolds,
                        contacts: inputs.contacts,
                        bodies: inputs.bodies,
                        poses: inputs.poses,
                        velocities: inputs.velocities,
                        solver_bodies: get(SOLVER_BODIES),
                        previous_tilts: get(TILTS[1 - p]),
                        color_order: order,
                        constraints: get(CONSTRAINTS),
                    },
                )
            }),
            integrate_velocities: k.integrate_velocities.bind(
                ctx,
                &IntegrateVelocitiesArgs {
                    params: &self.params,
                    bodies: inputs.bodies,
                    poses: inputs.poses,
                    solver_bodies: get(SOLVER_BODIES),
                    velocities: inputs.velocities,
                },
            ),
            integrate_positions: k.integrate_positions.bind(
                ctx,
                &IntegratePositionsArgs {
                    params: &self.params,
                    bodies: inputs.bodies,
                    poses: inputs.poses,
                    velocities: inputs.velocities,
                    solver_bodies: get(SOLVER_BODIES),
                },
            ),
            finalize_bodies: k.finalize_bodies.bind(
                ctx,
                &FinalizeBodiesArgs {
                    params: &self.params,
                    bodies: inputs.bodies,
                    solver_bodies: get(SOLVER_BODIES),
                    poses: inputs.poses,
                },
            ),
            store_impulses: both(&|p| {
                k.store_impulses.bind(
                    ctx,
                    &StoreImpulsesArgs {
                        contact_work: inputs.contact_work,
                        color_order: order,
                        constraints: get(CONSTRAINTS),
                        poses: inputs.poses,
                        contacts: inputs.contacts,
                        tilts: get(TILTS[p]),
                    },
                )
            }),
            passes,
            solve_fused: both(&|p| {
                k.solve_fused.bind(
                    ctx,
                    &SolveFusedArgs {
                        params: &self.params,
                        contact_work: inputs.contact_work,
                        manifolds: inputs.manifolds,
                        contacts: inputs.contacts,
                        bodies: inputs.bodies,
                        previous_colors: get(COLOR_STATE[1 - p]),
                        color_state: get(COLOR_STATE[p]),
                        color_marks: get(COLOR_MARKS),
                        color_scratch: get(COLOR_SCRATCH),
                        color_offsets: get(COLOR_OFFSETS),
                        color_order: order,
                        poses: inputs.poses,
                        velocities: inputs.velocities,
                        solver_bodies: get(SOLVER_BODIES),
                        constraints: get(CONSTRAINTS),
                        previous_tilts: get(TILTS[1 - p]),
                        tilts: get(TILTS[p]),
                    },
                )
            }),
            solve_fused_shared: both(&|p| {
                k.solve_fused_shared.bind(
                    ctx,
                    &SolveFusedSharedArgs {
                        params: &self.params,
                        contact_work: inputs.contact_work,
                        manifolds: inputs.manifolds,
                        contacts: inputs.contacts,
                        bodies: inputs.bodies,
                        previous_colors: get(COLOR_STATE[1 - p]),
                        color_state: get(COLOR_STATE[p]),
                        color_marks: get(COLOR_MARKS),
                        color_scratch: get(COLOR_SCRATCH),
                        color_offsets: get(COLOR_OFFSETS),
                        color_order: order,
                        poses: inputs.poses,
                        velocity_buffer: inputs.velocities,
                        solver_body_buffer: get(SOLVER_BODIES),
                        constraints: get(CONSTRAINTS),
                        previous_tilts: get(TILTS[1 - p]),
                        tilts: get(TILTS[p]),
                    },
                )
            }),
        }
    }
}
