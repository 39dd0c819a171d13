//! The solver for a batch of worlds (`GpuWorld::set_bodies_in_worlds`): the worlds' body
//! ranges, and [`SolvePath::Worlds`], one workgroup per world.

use super::*;
use crate::constants::MAX_WORKGROUPS_PER_DIMENSION;
use crate::solver::fused::WORLDS_SHARED_BODIES;

impl GpuSolver {
    /// Sets the independent worlds the bodies form: `first_bodies[w]` is world `w`'s first
    /// body (their `GpuBody::world`, numbered from 0 without gaps, each world's bodies one
    /// run), `bodies` the body count. With more than one, the coloring numbers each world's
    /// constraints from its first (`world_starts.wgsl`), so each world gets the colors it gets
    /// alone, and a step takes the wide path or [`SolvePath::Worlds`], never the fused one.
    pub fn set_worlds(&mut self, first_bodies: &[u32], bodies: u32) {
        self.worlds = (first_bodies.len() as u32).max(1);
        let mut table = Vec::with_capacity(first_bodies.len() + 2);
        table.push(first_bodies.len() as u32);
        table.extend_from_slice(first_bodies);
        table.push(bodies);
        self.max_world_bodies = table[1..]
            .windows(2)
            .map(|w| w[1] - w[0])
            .max()
            .unwrap_or(0);
        self.world_bodies = Some(table);
    }

    /// Independent worlds in the step.
    pub fn world_count(&self) -> u32 {
        self.worlds
    }

    /// Records [`SolvePath::Worlds`] into `pass`: each world's manifold range, then one
    /// workgroup per world (`solve_worlds`, or `solve_worlds_shared` with the bodies in
    /// workgroup memory where the device and the worlds' sizes allow). The encoder must have
    /// cleared the range buffers (`clear_world_ranges`).
    pub(super) fn record_worlds(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        groups: &BindGroups,
        work: &wgpu::Buffer,
    ) {
        let k = &self.pipelines;
        let p = self.parity;
        groups.color[p].record_world_starts(pass, k, work);
        let w = self.worlds;
        let x = w.min(MAX_WORKGROUPS_PER_DIMENSION);
        let shared = self.fused_memory.in_workgroup(0, self.ctx.info.device_type)
            && self.max_world_bodies <= WORLDS_SHARED_BODIES;
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
