//! The broad phase's two sorts: the bodies by sort key and the pairs by `(a, b)`, each as
//! one list (`rank_sort` for short lists, the radix sort above) or, in a step of several small
//! worlds, one workgroup per world (`sort_world_bodies`; `count_world_pairs`,
//! `scan_world_pairs`, `scatter_world_pairs`, `sort_world_pairs`). Every way gives the same
//! list: the radix sort's stable order.

use super::buffers::*;
use super::kernels::CollisionGroups;
use super::*;

impl GpuCollision {
    /// The body and pair sorts' plan for bodies of `shapes`: with several worlds, none of more
    /// than [`RANK_SORT_CAPACITY`] bodies, and at most one workgroup row of them, the world
    /// table is written (its buffer grown as needed) and the body sort takes one workgroup per
    /// world (`sort_world_bodies`); the workgroup count is returned. Where no world has more
    /// than [`WORLD_PAIR_SORT_MAX_BODIES`] bodies, the pairs are sorted by world too
    /// (`count_world_pairs` and the three after it). Otherwise 0: the whole list is sorted at
    /// once (`rank_sort` up to its capacity, the radix sort above it). The order is the same
    /// every way.
    pub(super) fn plan_world_sort(&mut self, shapes: &[GpuShape]) -> Result<u32, GpuError> {
        let starts = crate::kernels::rank_sort::world_body_starts(
            shapes.iter().map(|s| s.flags >> BODY_WORLD_SHIFT),
        );
        self.world_pair_sort = false;
        let Some(starts) = starts else {
            return Ok(0);
        };
        let worlds = starts.len() as u32 - 1;
        let largest = starts.windows(2).map(|w| w[1] - w[0]).max().unwrap_or(0);
        if worlds < 2 || largest > RANK_SORT_CAPACITY || worlds > MAX_WORKGROUPS_PER_DIMENSION {
            return Ok(0);
        }
        let mut table = Vec::with_capacity(starts.len() + 1);
        table.push(worlds);
        table.extend_from_slice(&starts);
        let u32s = |n: usize| (n * std::mem::size_of::<u32>()) as u64;
        self.pool
            .ensure(WORLD_BODY_STARTS, u32s(table.len()), STORAGE_USAGE)?;
        self.ctx.queue.write_buffer(
            self.pool.get(WORLD_BODY_STARTS),
            0,
            bytemuck::cast_slice(&table),
        );
        if largest <= WORLD_PAIR_SORT_MAX_BODIES {
            let counts = [
                (WORLD_PAIR_COUNTS, u32s(worlds as usize)),
                (WORLD_PAIR_STARTS, u32s(worlds as usize + 1)),
            ];
            self.pool.ensure_all(&counts, STORAGE_USAGE)?;
            self.world_pair_sort = true;
        }
        Ok(worlds)
    }

    /// Whether the steps sort their bodies and their pairs by world, one workgroup per world
    /// (`sort_world_bodies`, `sort_world_pairs`), rather than as one list; the order is the
    /// same either way ([`Self::set_bodies`] decides from the world sizes).
    pub fn sorts_by_world(&self) -> (bool, bool) {
        (self.world_sort_groups > 0, self.world_pair_sort)
    }

    /// Records the body sort (after `write_sort_keys`) into `pass`.
    pub(super) fn record_body_sort(&self, pass: &mut wgpu::ComputePass<'_>, g: &CollisionGroups) {
        let k = &self.kernels;
        // One dispatch instead of 24 for short lists and for steps of several small worlds.
        if let (true, Some(group)) = (self.world_sort_groups > 0, &g.world_body_sort) {
            k.sort_world_bodies
                .dispatch_workgroups(pass, group, self.world_sort_groups, 1);
        } else if self.body_count <= RANK_SORT_CAPACITY {
            k.rank_sort
                .dispatch_workgroups(pass, &g.small_body_sort, 1, 1);
        } else {
            self.radix
                .record(pass, &g.body_sort, self.pool.get(BODY_WORK));
        }
    }

    /// Records the pair sort of parity `p`'s pairs (after `plan_dispatch`) in its own timed
    /// pass.
    pub(super) fn record_pair_sort(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut StageTimer,
        g: &CollisionGroups,
        p: usize,
    ) {
        let k = &self.kernels;
        let pair_work = self.pool.get(PAIR_WORK[p]);
        let world_pairs = self
            .world_pair_sort
            .then_some(g.parity[p].world_pairs.as_ref())
            .flatten();
        if world_pairs.is_some() {
            encoder.clear_buffer(self.pool.get(WORLD_PAIR_COUNTS), 0, None);
        }
        let mut pass = timer.begin_pass(encoder, BROAD_PHASE_SORT_PAIRS);
        if let Some(w) = world_pairs {
            k.count_world_pairs
                .dispatch_work(&mut pass, &w.count, pair_work);
            k.scan_world_pairs
                .dispatch_workgroups(&mut pass, &w.scan, 1, 1);
            k.scatter_world_pairs
                .dispatch_work(&mut pass, &w.scatter, pair_work);
            k.sort_world_pairs
                .dispatch_workgroups(&mut pass, &w.sort, self.world_sort_groups, 1);
        } else if self.pair_capacity() <= RANK_SORT_CAPACITY {
            // A list no longer than its buffers' capacity: when that is at most the rank
            // sort's, every step's pairs fit it (the count is clamped to the capacity).
            k.rank_sort
                .dispatch_workgroups(&mut pass, &g.parity[p].small_pair_sort, 1, 1);
        } else {
            self.radix
                .record(&mut pass, &g.parity[p].pair_sort, pair_work);
        }
    }
}
