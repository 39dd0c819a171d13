//! The pipelines of the collision stages and their bind groups over the collision buffers.

use super::buffers::*;
use crate::GpuContext;
use crate::buffer_pool::BufferPool;
use crate::kernel::pipelines;
use crate::kernels::carry_impulses::CARRY_IMPULSES;
use crate::kernels::choose_axis::CHOOSE_AXIS;
use crate::kernels::collide_cuboids::COLLIDE_CUBOIDS;
use crate::kernels::compact_touching::{
    COUNT_TOUCHING, SCAN_TOUCHING, SCATTER_IMPULSES, WRITE_TOUCHING,
};
use crate::kernels::forget_pairs::FORGET_PAIRS;
use crate::kernels::gather_sweep_boxes::GATHER_SWEEP_BOXES;
use crate::kernels::match_pairs::MATCH_PAIRS;
use crate::kernels::plan_dispatch::PLAN_DISPATCH;
use crate::kernels::radix_sort::{
    RadixBindGroups, RadixBuffers, RadixSort, index_bits, plan_passes, result_copy,
};
use crate::kernels::rank_sort::{
    COUNT_WORLD_PAIRS, RANK_SORT, SCAN_WORLD_PAIRS, SCATTER_WORLD_PAIRS, SORT_WORLD_BODIES,
    SORT_WORLD_PAIRS,
};
use crate::kernels::remap_pairs::REMAP_PAIRS;
use crate::kernels::sweep_pairs::{LONG_PAIRS, SWEEP_PAIRS};
use crate::kernels::update_aabbs::UPDATE_AABBS;
use crate::kernels::write_sort_keys::WRITE_SORT_KEYS;

pipelines! {
    /// Every pipeline the collision stages dispatch (the radix sort's are [`RadixSort`]'s).
    pub struct CollisionKernels {
        update_aabbs: UPDATE_AABBS,
        choose_axis: CHOOSE_AXIS,
        write_sort_keys: WRITE_SORT_KEYS,
        /// The body and pair sorts of short lists.
        rank_sort: RANK_SORT,
        /// The body sort of a step of several small worlds, one workgroup per world.
        sort_world_bodies: SORT_WORLD_BODIES,
        /// The pair sort of a step of several small worlds: count, scan, scatter, sort.
        count_world_pairs: COUNT_WORLD_PAIRS,
        scan_world_pairs: SCAN_WORLD_PAIRS,
        scatter_world_pairs: SCATTER_WORLD_PAIRS,
        sort_world_pairs: SORT_WORLD_PAIRS,
        gather_sweep_boxes: GATHER_SWEEP_BOXES,
        sweep_pairs: SWEEP_PAIRS,
        long_pairs: LONG_PAIRS,
        plan_dispatch: PLAN_DISPATCH,
        match_pairs: MATCH_PAIRS,
        collide_cuboids: COLLIDE_CUBOIDS,
        carry_impulses: CARRY_IMPULSES,
        count_touching: COUNT_TOUCHING,
        scan_touching: SCAN_TOUCHING,
        write_touching: WRITE_TOUCHING,
        scatter_impulses: SCATTER_IMPULSES,
        /// Last step's pairs of chosen worlds dropped (a reset of those worlds).
        forget_pairs: FORGET_PAIRS,
        /// Last step's pairs renumbered after a new upload order.
        remap_pairs: REMAP_PAIRS,
    }
}

/// Bind groups of one step parity (what depends on which pair set is current).
#[derive(Debug)]
pub struct ParityGroups {
    /// `sweep_pairs`, appending into this parity's copy 0.
    pub sweep: wgpu::BindGroup,
    /// `long_pairs`, appending into this parity's copy 0.
    pub long_pairs: wgpu::BindGroup,
    /// `plan_dispatch` into this parity's work list.
    pub plan: wgpu::BindGroup,
    /// The canonical pair sort.
    pub pair_sort: RadixBindGroups,
    /// The pair sort when the pair buffers hold at most `RANK_SORT_CAPACITY` pairs.
    pub small_pair_sort: wgpu::BindGroup,
    /// `match_pairs` against the other parity.
    pub match_pairs: wgpu::BindGroup,
    /// `collide_cuboids`.
    pub collide: wgpu::BindGroup,
    /// `carry_impulses` from the other parity.
    pub carry: wgpu::BindGroup,
    /// The compaction's, once its buffers exist ([`TOUCHING_BUFFERS`]).
    pub touching: Option<TouchingGroups>,
    /// The pair sort by world, where the pool holds its buffers.
    pub world_pairs: Option<WorldPairGroups>,
}

/// The pair sort by world's bind groups, of one parity.
#[derive(Debug)]
pub struct WorldPairGroups {
    /// `count_world_pairs`.
    pub count: wgpu::BindGroup,
    /// `scan_world_pairs`.
    pub scan: wgpu::BindGroup,
    /// `scatter_world_pairs`, from the result copy into the other copy.
    pub scatter: wgpu::BindGroup,
    /// `sort_world_pairs`, from the other copy back into the result copy.
    pub sort: wgpu::BindGroup,
}

/// Bind groups of the touching compaction, for one parity.
#[derive(Debug)]
pub struct TouchingGroups {
    /// `count_touching` over this parity's manifolds.
    pub count_touching: wgpu::BindGroup,
    /// `scan_touching` of this parity's pair count.
    pub scan_touching: wgpu::BindGroup,
    /// `write_touching` from this parity's manifolds and points.
    pub write_touching: wgpu::BindGroup,
}

/// All bind groups, valid for one buffer-pool generation and body count.
#[derive(Debug)]
pub struct CollisionGroups {
    /// Pool generation they were built at.
    pub generation: u64,
    /// Key bits of the pair sort (from the body count) they were built for.
    pub pair_bits: u32,
    /// `update_aabbs`.
    pub update_aabbs: wgpu::BindGroup,
    /// `choose_axis`.
    pub choose_axis: wgpu::BindGroup,
    /// `write_sort_keys`.
    pub write_sort_keys: wgpu::BindGroup,
    /// The body sort.
    pub body_sort: RadixBindGroups,
    /// The body sort of at most `RANK_SORT_CAPACITY` bodies (in place, in the radix sort's
    /// result copy).
    pub small_body_sort: wgpu::BindGroup,
    /// The body sort by world (`sort_world_bodies`, in place in the radix sort's result copy),
    /// where the pool holds the world table.
    pub world_body_sort: Option<wgpu::BindGroup>,
    /// `gather_sweep_boxes`.
    pub gather_sweep_boxes: wgpu::BindGroup,
    /// Per parity.
    pub parity: [ParityGroups; 2],
}

/// Bind groups over `pool` for `bodies` bodies.
pub fn build_groups(
    ctx: &GpuContext,
    kernels: &CollisionKernels,
    radix: &RadixSort,
    pool: &BufferPool,
    bodies: u32,
) -> CollisionGroups {
    let b = |name: &'static str| pool.get(name);
    // The body kernels' buffers by binding name.
    let body = |name: &'static str| match name {
        "work" => b(BODY_WORK),
        "keys" => b(SORT_KEYS[0]),
        "values" => b(SORT_BODIES[0]),
        "sorted_bodies" => b(SORT_BODIES[BODY_RESULT_COPY]),
        "params" => b(SWEEP_PARAMS),
        name => b(name),
    };
    let body_passes = plan_passes(&[(true, u32::BITS)]);
    assert_eq!(result_copy(&body_passes), BODY_RESULT_COPY);
    let body_sort = radix.bind(
        ctx,
        &RadixBuffers {
            work: b(BODY_WORK),
            first: [b(SORT_KEYS[0]), b(SORT_KEYS[1])],
            second: [b(SORT_BODIES[0]), b(SORT_BODIES[1])],
            tile_counts: b(BODY_TILES),
        },
        &body_passes,
    );
    // Pairs sort by b, then stably by a: lexicographic (a, b), the CPU's order.
    let pair_bits = index_bits(bodies);
    let pair_passes = plan_passes(&[(false, pair_bits), (true, pair_bits)]);
    assert_eq!(result_copy(&pair_passes), PAIR_RESULT_COPY);
    // The pair kernels' buffers by binding name, for parity `p` (last step's is `q`). The
    // sweep appends into copy 0, the pair sort's result copy (asserted above), where the rank
    // sort sorts in place and the kernels after the sort read.
    let pair = |p: usize| {
        let q = 1 - p;
        move |name: &'static str| match name {
            "work" => b(PAIR_WORK[p]),
            "previous_work" => b(PAIR_WORK[q]),
            "pair_a" | "keys" => b(PAIR_A[p][PAIR_RESULT_COPY]),
            "pair_b" | "values" => b(PAIR_B[p][PAIR_RESULT_COPY]),
            "scratch_a" => b(PAIR_A[p][1 - PAIR_RESULT_COPY]),
            "scratch_b" => b(PAIR_B[p][1 - PAIR_RESULT_COPY]),
            "previous_a" => b(PAIR_A[q][PAIR_RESULT_COPY]),
            "previous_b" => b(PAIR_B[q][PAIR_RESULT_COPY]),
            "manifolds" => b(MANIFOLDS[p]),
            "previous_manifolds" => b(MANIFOLDS[q]),
            "contacts" => b(CONTACTS[p]),
            "previous_contacts" => b(CONTACTS[q]),
            "locals" => b(LOCAL_MANIFOLDS[p]),
            "previous_locals" => b(LOCAL_MANIFOLDS[q]),
            "tile_totals" | "tile_offsets" => b(TOUCHING_TILES),
            "params" => b(SWEEP_PARAMS),
            name => b(name),
        }
    };
    let parity = [0, 1].map(|p| ParityGroups {
        sweep: kernels.sweep_pairs.bind_named(ctx, pair(p)),
        long_pairs: kernels.long_pairs.bind_named(ctx, pair(p)),
        plan: kernels.plan_dispatch.bind_named(ctx, pair(p)),
        pair_sort: radix.bind(
            ctx,
            &RadixBuffers {
                work: b(PAIR_WORK[p]),
                first: [b(PAIR_A[p][0]), b(PAIR_A[p][1])],
                second: [b(PAIR_B[p][0]), b(PAIR_B[p][1])],
                tile_counts: b(PAIR_TILES),
            },
            &pair_passes,
        ),
        small_pair_sort: kernels.rank_sort.bind_named(ctx, pair(p)),
        match_pairs: kernels.match_pairs.bind_named(ctx, pair(p)),
        collide: kernels.collide_cuboids.bind_named(ctx, |name| match name {
            "params" => b(NARROW_PARAMS),
            name => pair(p)(name),
        }),
        carry: kernels.carry_impulses.bind_named(ctx, pair(p)),
        world_pairs: pool.contains(WORLD_PAIR_COUNTS).then(|| WorldPairGroups {
            count: kernels.count_world_pairs.bind_named(ctx, pair(p)),
            scan: kernels.scan_world_pairs.bind_named(ctx, pair(p)),
            scatter: kernels.scatter_world_pairs.bind_named(ctx, pair(p)),
            sort: kernels.sort_world_pairs.bind_named(ctx, pair(p)),
        }),
        touching: pool.contains(TOUCHING).then(|| TouchingGroups {
            count_touching: kernels.count_touching.bind_named(ctx, pair(p)),
            scan_touching: kernels.scan_touching.bind_named(ctx, pair(p)),
            write_touching: kernels.write_touching.bind_named(ctx, pair(p)),
        }),
    });
    CollisionGroups {
        generation: pool.generation(),
        pair_bits,
        update_aabbs: kernels.update_aabbs.bind_named(ctx, |name| match name {
            "params" => b(UPDATE_PARAMS),
            name => body(name),
        }),
        choose_axis: kernels.choose_axis.bind_named(ctx, body),
        write_sort_keys: kernels.write_sort_keys.bind_named(ctx, body),
        body_sort,
        // In place in copy 0, where the radix sort's even number of passes leaves its result
        // (asserted above).
        small_body_sort: kernels.rank_sort.bind_named(ctx, body),
        world_body_sort: pool
            .contains(WORLD_BODY_STARTS)
            .then(|| kernels.sort_world_bodies.bind_named(ctx, body)),
        gather_sweep_boxes: kernels.gather_sweep_boxes.bind_named(ctx, body),
        parity,
    }
}
