//! The solver for a batch of worlds (`GpuWorld::set_bodies_in_worlds`): the worlds' body
//! ranges, and [`SolvePath::Worlds`], one workgroup per group of worlds.

use super::*;
use crate::constants::MAX_WORKGROUPS_PER_DIMENSION;
use crate::solver::fused::WORLDS_SHARED_BODIES;
use crate::solver::path::world_groups;

impl GpuSolver {
    /// Sets the independent worlds the bodies form: `first_bodies[w]` is world `w`'s first
    /// body (their `GpuBody::world`, numbered from 0 without gaps, each world's bodies one
    /// run), `bodies` the body count. With more than one, the coloring numbers each world's
    /// constraints from its first (`world_starts.wgsl`), so each world gets the colors it gets
    /// alone, and a step takes the wide path or [`SolvePath::Worlds`], never the fused one.
    pub fn set_worlds(&mut self, first_bodies: &[u32], bodies: u32) {
        self.worlds = (first_bodies.len() as u32).max(1);
        let mut table = Vec::with_capacity(2 * first_bodies.len() + 4);
        table.push(first_bodies.len() as u32);
        table.extend_from_slice(first_bodies);
        table.push(bodies);
        self.world_bodies = Some(table);
        self.group_worlds();
    }

    /// How [`SolvePath::Worlds`] packs the worlds into workgroups from the next step on
    /// ([`WorldGrouping`]; the same bits either way).
    pub fn set_world_grouping(&mut self, grouping: WorldGrouping) {
        self.world_grouping = grouping;
        self.group_worlds();
    }

    /// Packs the worlds of the table into groups ([`world_groups`]) and appends the groups to
    /// the table: [worlds, first bodies.., bodies, groups, first worlds.., worlds].
    fn group_worlds(&mut self) {
        let Some(table) = self.world_bodies.as_mut() else {
            return;
        };
        let worlds = table[0];
        table.truncate(worlds as usize + 2);
        let bodies = table[worlds as usize + 1];
        let groups = world_groups(&table[1..], self.world_grouping.group_bodies(bodies));
        self.world_groups = groups.len() as u32;
        // The largest group's bodies: the workgroup copies of solve_worlds_shared hold them.
        self.max_group_bodies = groups
            .iter()
            .zip(groups.iter().skip(1).chain([&worlds]))
            .map(|(&g, &next)| table[1 + next as usize] - table[1 + g as usize])
            .max()
            .unwrap_or(0);
        table.push(groups.len() as u32);
        table.extend_from_slice(&groups);
        table.push(worlds);
    }

    /// Groups of worlds [`SolvePath::Worlds`] runs, one workgroup each ([`WorldGrouping`]).
    pub fn world_group_count(&self) -> u32 {
        self.world_groups
    }

    /// Independent worlds in the step.
    pub fn world_count(&self) -> u32 {
        self.worlds
    }

    /// Records [`SolvePath::Worlds`] into `pass`: each world's manifold range, then one
    /// workgroup per group of worlds ([`world_groups`]; `solve_worlds`, or
    /// `solve_worlds_shared` with the bodies in workgroup memory where the device and the
    /// groups' sizes allow). The encoder must have cleared the range buffers
    /// (`clear_world_ranges`).
    pub(super) fn record_worlds(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        groups: &BindGroups,
        work: &wgpu::Buffer,
    ) {
        let k = &self.pipelines;
        let p = self.parity;
        groups.color[p].record_world_starts(pass, k, work);
        let w = self.world_groups.max(1);
        let x = w.min(MAX_WORKGROUPS_PER_DIMENSION);
        let shared = self.fused_memory.in_workgroup(0, self.ctx.info.device_type)
            && self.max_group_bodies <= WORLDS_SHARED_BODIES;
        let (kernel, group) = if shared {
            (&k.solve_worlds_shared, &groups.solve_worlds_shared[p])
        } else {
            (&k.solve_worlds, &groups.solve_worlds[p])
        };
        kernel.dispatch_workgroups(pass, group, x, w.div_ceil(x));
    }

    /// Writes the worlds' body table and clears their manifold ranges, before
    /// [`Self::record_worlds`]. The table is small (a word per world) and written every step,
    /// so a reallocated buffer never holds a stale one.
    pub(super) fn clear_world_ranges(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(table) = &self.world_bodies {
            self.ctx.queue.write_buffer(
                self.pool.get(WORLD_BODIES),
                0,
                bytemuck::cast_slice(table),
            );
        }
        encoder.clear_buffer(self.pool.get(WORLD_FIRST), 0, None);
        encoder.clear_buffer(self.pool.get(WORLD_END), 0, None);
    }
}
