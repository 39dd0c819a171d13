//! The solver for a batch of worlds (`GpuWorld::set_bodies_in_worlds`): the worlds' body
//! ranges, and [`SolvePath::Worlds`], one workgroup per group of worlds.

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
        let mut table = Vec::with_capacity(2 * first_bodies.len() + 4);
        table.push(first_bodies.len() as u32);
        table.extend_from_slice(first_bodies);
        table.push(bodies);
        let groups = world_groups(&table[1..], WORLD_GROUP_BODIES);
        self.world_groups = groups.len() as u32;
        // The largest group's bodies: the workgroup copies of solve_worlds_shared hold them.
        self.max_group_bodies = groups
            .iter()
            .zip(groups.iter().skip(1).chain([&(first_bodies.len() as u32)]))
            .map(|(&g, &next)| table[1 + next as usize] - table[1 + g as usize])
            .max()
            .unwrap_or(0);
        table.push(groups.len() as u32);
        table.extend_from_slice(&groups);
        table.push(first_bodies.len() as u32);
        self.world_bodies = Some(table);
    }

    /// Independent worlds in the step.
    pub fn world_count(&self) -> u32 {
        self.worlds
    }

    /// Records [`SolvePath::Worlds`] into `pass`: each world's manifold range, then one
    /// workgroup per group of worlds ([`world_groups`]; `solve_worlds`, or `solve_worlds_shared`
    /// with the bodies in workgroup memory where the device and the groups' sizes allow). The encoder must have
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

/// Bodies a group of worlds of [`SolvePath::Worlds`] holds at most (a world with more is a
/// group alone): the bodies' copies of `solve_worlds_shared` hold this many.
pub const WORLD_GROUP_BODIES: u32 = WORLDS_SHARED_BODIES;

/// Consecutive worlds packed into groups of at most `max_bodies` bodies, greedily in world
/// order (a larger world alone): the first world of each group. `starts` holds each world's
/// first body, then the body count. One workgroup runs a group as one world: its worlds share
/// no body, so each constraint is colored and solved as in its world alone, while the worlds
/// of a small batch fill the workgroup's lanes (a column of 20 has about 10 constraints per
/// color, a third of a 32-thread workgroup).
pub fn world_groups(starts: &[u32], max_bodies: u32) -> Vec<u32> {
    let mut groups = Vec::new();
    let mut group_first_body = 0;
    for (w, pair) in starts.windows(2).enumerate() {
        if groups.is_empty() || pair[1] - group_first_body > max_bodies {
            groups.push(w as u32);
            group_first_body = pair[0];
        }
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::world_groups;

    #[test]
    fn groups_take_consecutive_worlds_up_to_the_body_bound() {
        // Worlds of 21 bodies: three fill 63 of 64, a fourth would make 84.
        let starts: Vec<u32> = (0..=7).map(|w| 21 * w).collect();
        assert_eq!(world_groups(&starts, 64), vec![0, 3, 6]);
        // A bound of one body: every world alone (the one-world-per-workgroup layout).
        assert_eq!(world_groups(&starts, 1), (0..7).collect::<Vec<_>>());
        // A world over the bound is a group alone, and the packing resumes after it.
        let starts = [0, 10, 110, 120, 150, 164];
        assert_eq!(world_groups(&starts, 64), vec![0, 1, 2]);
        // Two worlds that exactly fill the bound share a group.
        assert_eq!(world_groups(&[0, 32, 64], 64), vec![0]);
        // One world, and no world at all.
        assert_eq!(world_groups(&[0, 5], 64), vec![0]);
        assert!(world_groups(&[0], 64).is_empty());
    }
}
