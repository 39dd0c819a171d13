//! The collision stages' device buffers, by name, and their sizes.
//!
//! Pair lists, manifolds and contacts exist once per step parity: step `n` writes the set
//! `n % 2` while the other set still holds step `n - 1`, whose sorted pairs `match_pairs`
//! searches and whose impulses and local manifolds `carry_impulses` reads. Each parity's pair arrays have two
//! copies, the radix sort's ping-pong; the sorted result lands in copy
//! [`PAIR_RESULT_COPY`] (the pair sort always runs an even number of passes); the other copy
//! is scratch of the sort alone, one buffer for both parities.
//!
//! A buffer that the kernels bind under one name is called by that name, so that the bind
//! groups look the kernels' arguments up by binding name (`kernels::build_groups`); the
//! others (per parity or copy, or bound under several names) are looked up explicitly there.

use crate::buffer_pool::{BufferPool, STORAGE_USAGE, UNIFORM_USAGE, bytes_of};
use crate::kernels::radix_sort::tile_count_len;
use crate::layout::{
    GpuAabb, GpuCollisionGroups, GpuContact, GpuLocalManifold, GpuManifold, GpuPose, GpuShape,
    GpuSweepBox, GpuTouching, GpuVelocity, SweepAxis, TouchingCounts, WorkList,
};
use crate::{GpuError, MAX_MANIFOLD_POINTS};

/// Copy of a parity's pair arrays that holds the sorted list.
pub const PAIR_RESULT_COPY: usize = 0;
/// Copy of the body sort arrays that holds the sorted order (8 passes over 32-bit keys).
pub const BODY_RESULT_COPY: usize = 0;

/// Per-body inputs.
pub const POSES: &str = "poses";
/// Per-body velocities.
pub const VELOCITIES: &str = "velocities";
/// Per-body shapes and flags.
pub const SHAPES: &str = "shapes";
/// Per world, 0 or its first body plus one: the worlds whose pairs `forget_pairs` drops.
pub const FORGET_WORLDS: &str = "forget worlds";
/// Per body of the last upload, its new index or where its world's pairs drop
/// (`remap_pairs.wgsl`).
pub const REMAP: &str = "remap";
/// Per-body AABBs.
pub const AABBS: &str = "aabbs";
/// The bodies' `WorkList` (written by the host).
pub const BODY_WORK: &str = "body work list";
/// `SweepAxis`.
pub const SWEEP_AXIS: &str = "sweep_axis";
/// Body sort keys, two copies.
pub const SORT_KEYS: [&str; 2] = ["sort keys 0", "sort keys 1"];
/// Body sort values (body indices), two copies.
pub const SORT_BODIES: [&str; 2] = ["sorted bodies 0", "sorted bodies 1"];
/// AABBs in sweep order.
pub const SWEEP_BOXES: &str = "sweep_boxes";
/// `GpuCollisionGroups`, one per body.
pub const GROUPS: &str = "groups";
/// Tile counts of the body sort.
pub const BODY_TILES: &str = "body sort tiles";
/// The long box count and list (`shaders/common/sweep.wgsl`).
pub const LONG_BOXES: &str = "long_boxes";
/// The sweep's append counter.
pub const PAIR_COUNTER: &str = "counter";
/// First bodies of the pairs, `[parity][copy]`. Copy 1 is only the pair sort's ping-pong
/// scratch, dead once the sort has left its result in copy 0, so both parities share it.
pub const PAIR_A: [[&str; 2]; 2] = [
    ["pair a 0.0", "pair a scratch"],
    ["pair a 1.0", "pair a scratch"],
];
/// Second bodies of the pairs, `[parity][copy]` (copy 1 shared, as [`PAIR_A`]'s).
pub const PAIR_B: [[&str; 2]; 2] = [
    ["pair b 0.0", "pair b scratch"],
    ["pair b 1.0", "pair b scratch"],
];
/// The pairs' `WorkList`, per parity.
pub const PAIR_WORK: [&str; 2] = ["pair work list 0", "pair work list 1"];
/// Tile counts of the pair sort.
pub const PAIR_TILES: &str = "pair sort tiles";
/// Last step's index of each pair.
pub const PREVIOUS_INDEX: &str = "previous_index";
/// Manifolds, per parity.
pub const MANIFOLDS: [&str; 2] = ["manifolds 0", "manifolds 1"];
/// Contact points, per parity.
pub const CONTACTS: [&str; 2] = ["contacts 0", "contacts 1"];
/// Manifolds in their body A's frame (`GpuLocalManifold`), per parity: what the next step
/// matches points whose ids changed against.
pub const LOCAL_MANIFOLDS: [&str; 2] = ["local manifolds 0", "local manifolds 1"];
/// Per-tile (manifolds in contact, points) totals of the compaction.
pub const TOUCHING_TILES: &str = "touching tiles";
/// `TouchingCounts`.
pub const TOUCHING_COUNTS: &str = "counts";
/// `GpuTouching`, one per manifold in contact.
pub const TOUCHING: &str = "touching";
/// Manifolds in contact, dense.
pub const TOUCHING_MANIFOLDS: &str = "touching_manifolds";
/// Their points, dense.
pub const TOUCHING_POINTS: &str = "touching_points";
/// Impulses uploaded in dense point order for `scatter_impulses`.
pub const IMPULSE_UPLOAD: &str = "impulses";
/// `ScatterParams`.
pub const SCATTER_PARAMS: &str = "scatter params";
/// `UpdateAabbsParams`.
pub const UPDATE_PARAMS: &str = "update_aabbs params";
/// `SweepParams`.
pub const SWEEP_PARAMS: &str = "sweep params";
/// `NarrowParams`.
pub const NARROW_PARAMS: &str = "narrow params";
/// The world count, each world's first body and then the body count
/// (`kernels::rank_sort::world_body_starts` after the count), for `sort_world_bodies` and
/// `scan_world_pairs`; held only while a step of several worlds sorts its bodies by world.
pub const WORLD_BODY_STARTS: &str = "world_body_starts";
/// Pairs per world (`count_world_pairs`, `scatter_world_pairs`), cleared before each step's
/// pair sort by world; held only while the step sorts its pairs by world.
pub const WORLD_PAIR_COUNTS: &str = "world_pair_counts";
/// Each world's first pair slot, then the pair count (`scan_world_pairs`).
pub const WORLD_PAIR_STARTS: &str = "world_pair_starts";

/// The buffers kept in two parities, this step's and the last step's, left out of the step
/// check's checkpoints ([`BufferPool::with_per_step`]). A step writes only its own parity:
/// every kernel that reads the last step's copies binds them read-only (`match_pairs`,
/// `collide_cuboids`, `carry_impulses`, `contact_begins`, `contact_ends`), so a step that is undone leaves them
/// as they were, and its own parity, which held the step before last, is rewritten by the
/// step taken again before anything reads it (rolling back the parity counter restores
/// which is which). They are most of the collision stage's memory: a manifold, four contact
/// points and a local manifold per pair slot and parity.
pub const PARITY_BUFFERS: [&str; 16] = [
    PAIR_A[0][0],
    PAIR_A[0][1],
    PAIR_A[1][0],
    PAIR_A[1][1],
    PAIR_B[0][0],
    PAIR_B[0][1],
    PAIR_B[1][0],
    PAIR_B[1][1],
    PAIR_WORK[0],
    PAIR_WORK[1],
    MANIFOLDS[0],
    MANIFOLDS[1],
    CONTACTS[0],
    CONTACTS[1],
    LOCAL_MANIFOLDS[0],
    LOCAL_MANIFOLDS[1],
];

/// The buffers a checkpoint leaves out ([`BufferPool::with_per_step`]): the parity buffers,
/// and the scratch of one step that every step rewrites in full before reading it: the body
/// sort's keys and values (`write_sort_keys` writes every body's, the sort and
/// `gather_sweep_boxes` read them), the sweep boxes (`gather_sweep_boxes` writes every body's,
/// `sweep_pairs` and `long_pairs` read them) and `previous_index` (`match_pairs` writes it for
/// every pair of the step, `collide_cuboids` reads it for the same pairs). Those four are one
/// to eight words per body that the step check need not copy. And the pair sort by world's
/// counts and starts (cleared, then written, by each step's sort).
pub const PER_STEP_BUFFERS: [&str; 24] = [
    PARITY_BUFFERS[0],
    PARITY_BUFFERS[1],
    PARITY_BUFFERS[2],
    PARITY_BUFFERS[3],
    PARITY_BUFFERS[4],
    PARITY_BUFFERS[5],
    PARITY_BUFFERS[6],
    PARITY_BUFFERS[7],
    PARITY_BUFFERS[8],
    PARITY_BUFFERS[9],
    PARITY_BUFFERS[10],
    PARITY_BUFFERS[11],
    PARITY_BUFFERS[12],
    PARITY_BUFFERS[13],
    PARITY_BUFFERS[14],
    PARITY_BUFFERS[15],
    SORT_KEYS[0],
    SORT_KEYS[1],
    SORT_BODIES[0],
    SORT_BODIES[1],
    SWEEP_BOXES,
    PREVIOUS_INDEX,
    WORLD_PAIR_COUNTS,
    WORLD_PAIR_STARTS,
];

/// Makes every body-sized buffer hold `bodies`; true when any was reallocated.
pub fn ensure_body_buffers(pool: &mut BufferPool, bodies: u32) -> Result<bool, GpuError> {
    let n = u64::from(bodies);
    let storage = [
        (POSES, bytes_of::<GpuPose>(n)),
        (VELOCITIES, bytes_of::<GpuVelocity>(n)),
        (SHAPES, bytes_of::<GpuShape>(n)),
        (AABBS, bytes_of::<GpuAabb>(n)),
        (BODY_WORK, bytes_of::<WorkList>(1)),
        (SWEEP_AXIS, bytes_of::<SweepAxis>(1)),
        (SORT_KEYS[0], bytes_of::<u32>(n)),
        (SORT_KEYS[1], bytes_of::<u32>(n)),
        (SORT_BODIES[0], bytes_of::<u32>(n)),
        (SORT_BODIES[1], bytes_of::<u32>(n)),
        (SWEEP_BOXES, bytes_of::<GpuSweepBox>(n)),
        (GROUPS, bytes_of::<GpuCollisionGroups>(n)),
        (LONG_BOXES, crate::kernels::sweep_pairs::LONG_BOXES_BYTES),
        (BODY_TILES, bytes_of::<u32>(tile_count_len(bodies))),
    ];
    let params = [(UPDATE_PARAMS, 16), (SWEEP_PARAMS, 16), (NARROW_PARAMS, 16)];
    Ok(pool.ensure_all(&storage, STORAGE_USAGE)? | pool.ensure_all(&params, UNIFORM_USAGE)?)
}

/// Makes every pair-sized buffer hold `capacity` pairs; true when any was reallocated.
pub fn ensure_pair_buffers(pool: &mut BufferPool, capacity: u32) -> Result<bool, GpuError> {
    let n = u64::from(capacity);
    let points = n * u64::from(MAX_MANIFOLD_POINTS);
    let mut grew = pool.ensure(PAIR_COUNTER, bytes_of::<u32>(1), STORAGE_USAGE)?;
    for p in 0..2 {
        let parity = [
            (PAIR_A[p][0], bytes_of::<u32>(n)),
            (PAIR_B[p][0], bytes_of::<u32>(n)),
            (PAIR_A[p][1], bytes_of::<u32>(n)),
            (PAIR_B[p][1], bytes_of::<u32>(n)),
            (PAIR_WORK[p], bytes_of::<WorkList>(1)),
            (MANIFOLDS[p], bytes_of::<GpuManifold>(n)),
            (CONTACTS[p], bytes_of::<GpuContact>(points)),
            (LOCAL_MANIFOLDS[p], bytes_of::<GpuLocalManifold>(n)),
        ];
        grew |= pool.ensure_all(&parity, STORAGE_USAGE)?;
    }
    let shared = [
        (PAIR_TILES, bytes_of::<u32>(tile_count_len(capacity))),
        (PREVIOUS_INDEX, bytes_of::<u32>(n)),
    ];
    grew |= pool.ensure_all(&shared, STORAGE_USAGE)?;
    Ok(grew | pool.ensure(SCATTER_PARAMS, 16, UNIFORM_USAGE)?)
}

/// The dense list of the manifolds in contact, which only a readback asking for `touching`
/// writes (`GpuWorld`'s step never does): allocated on the first such readback, so a world
/// that never asks for it does not hold (and its step check does not copy) a manifold and
/// four points per pair slot for nothing.
pub const TOUCHING_BUFFERS: [&str; 5] = [
    TOUCHING_TILES,
    TOUCHING_COUNTS,
    TOUCHING,
    TOUCHING_MANIFOLDS,
    TOUCHING_POINTS,
];

/// Makes the dense touching list ([`TOUCHING_BUFFERS`]) hold `capacity` pairs; true when any
/// was reallocated.
pub fn ensure_touching_buffers(pool: &mut BufferPool, capacity: u32) -> Result<bool, GpuError> {
    let n = u64::from(capacity);
    let points = n * u64::from(MAX_MANIFOLD_POINTS);
    let tiles = u64::from(capacity.div_ceil(crate::WORKGROUP_SIZE));
    let sizes = [
        (TOUCHING_TILES, bytes_of::<[u32; 2]>(tiles)),
        (TOUCHING_COUNTS, bytes_of::<TouchingCounts>(1)),
        (TOUCHING, bytes_of::<GpuTouching>(n)),
        (TOUCHING_MANIFOLDS, bytes_of::<GpuManifold>(n)),
        (TOUCHING_POINTS, bytes_of::<GpuContact>(points)),
    ];
    pool.ensure_all(&sizes, STORAGE_USAGE)
}

/// The buffers one step's stages hand to each other: the world's bodies and what the
/// collision stages write (the GPU solver reads the manifolds and writes poses, velocities
/// and contact impulses; the sleep stage reads the manifolds and AABBs).
#[derive(Clone, Copy, Debug)]
pub struct StepBuffers<'a> {
    /// `array<GpuBody>`: the solver's bodies (sleeping ones are made fixed in it).
    pub bodies: &'a wgpu::Buffer,
    /// `array<GpuPose>`, one per body.
    pub poses: &'a wgpu::Buffer,
    /// `array<GpuVelocity>`, one per body.
    pub velocities: &'a wgpu::Buffer,
    /// `array<GpuShape>`, one per body (sleeping ones are flagged static in it).
    pub shapes: &'a wgpu::Buffer,
    /// `array<GpuAabb>`, one per body.
    pub aabbs: &'a wgpu::Buffer,
    /// The manifolds' `WorkList` (count and indirect dispatch size, produced on the GPU).
    pub contact_work: &'a wgpu::Buffer,
    /// `array<GpuManifold>`: one per candidate pair (`len == 0` when not in contact).
    pub manifolds: &'a wgpu::Buffer,
    /// `array<GpuContact>`, `MAX_MANIFOLD_POINTS` per manifold: carried impulses in,
    /// solved impulses out.
    pub contacts: &'a wgpu::Buffer,
}

/// The buffers of the step recorded with `parity`, beside the world's `bodies`.
pub fn step_buffers<'a>(
    pool: &'a BufferPool,
    parity: usize,
    bodies: &'a wgpu::Buffer,
) -> StepBuffers<'a> {
    StepBuffers {
        bodies,
        poses: pool.get(POSES),
        velocities: pool.get(VELOCITIES),
        shapes: pool.get(SHAPES),
        aabbs: pool.get(AABBS),
        contact_work: pool.get(PAIR_WORK[parity]),
        manifolds: pool.get(MANIFOLDS[parity]),
        contacts: pool.get(CONTACTS[parity]),
    }
}
