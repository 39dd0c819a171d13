//! The collision stages on the GPU: `update_aabbs`, `broad_phase` and `narrow_phase`,
//! recorded into a caller's command encoder with no host round trip in between.
//!
//! ```text
//! update_aabbs   poses, velocities, shapes -> aabbs
//! broad_phase    choose_axis -> write_sort_keys -> radix sort (bodies, 32-bit keys; up to
//!                1,024 bodies rank_sort, one workgroup, the same order)
//!                -> gather_sweep_boxes (long boxes listed) -> sweep_pairs + long_pairs
//!                (atomic append)
//!                -> plan_dispatch (count -> work list)
//!                -> radix sort (pairs by b, then by a: canonical order, indirect; up to
//!                1,024 pair slots rank_sort by (a, b), one workgroup)
//! narrow_phase   match_pairs (last step's index) -> collide_cuboids -> carry_impulses
//!                (by feature id, else by position in body A's frame; all three
//!                dispatched indirectly from the pair work list)
//! ```

pub mod buffers;
pub mod kernels;
pub mod snapshot;
pub mod validate;

mod pair_history;
mod reads;
mod saved;
mod sorts;

pub use buffers::StepBuffers;
use buffers::*;
use kernels::{CollisionGroups, CollisionKernels, build_groups};
pub use snapshot::{CollisionSnapshot, ReadbackRequest};

use crate::buffer_pool::{BufferPool, STORAGE_USAGE};
use crate::constants::MAX_WORKGROUPS_PER_DIMENSION;
use crate::kernel::Kernel;
use crate::kernels::collide_cuboids::{COLLIDE_CUBOIDS, collide_cuboids_kernel};
use crate::kernels::radix_sort::RadixSort;
use crate::kernels::rank_sort::{RANK_SORT_CAPACITY, WORLD_PAIR_SORT_MAX_BODIES};
use crate::layout::{
    BODY_WORLD_SHIFT, GpuAabb, GpuCollisionGroups, GpuContact, GpuLocalManifold, GpuManifold,
    GpuPose, GpuShape, GpuSweepBox, GpuTouching, GpuVelocity, NarrowParams, ScatterParams,
    SweepAxis, SweepParams, TouchingCounts, UpdateAabbsParams, WorkList,
};
use crate::readback::{Mapped, Readback, Region, Ticket};
use crate::{GpuContext, GpuError, MAX_BODIES, MAX_MANIFOLD_POINTS, StageTimer};

/// Timer name of the `update_aabbs` stage's pass.
pub const UPDATE_AABBS: &str = "update_aabbs";
/// Timer name of the broad phase's first pass: sweep axis, keys, body sort.
pub const BROAD_PHASE_SORT_BODIES: &str = "broad_phase: sort bodies";
/// Timer name of the broad phase's second pass: the sweep and the pair count.
pub const BROAD_PHASE_SWEEP: &str = "broad_phase: sweep";
/// Timer name of the broad phase's third pass: the canonical pair sort.
pub const BROAD_PHASE_SORT_PAIRS: &str = "broad_phase: sort pairs";
/// Timer name of the `narrow_phase` stage's pass.
pub const NARROW_PHASE: &str = "narrow_phase";

/// Settings of the collision stages.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CollisionConfig {
    /// Speculative margin (m): AABBs grow by it, and points this far apart are reported.
    pub margin: f32,
    /// Time step (s): AABBs sweep by velocity times `dt`, margins grow by closing speed.
    pub dt: f32,
    /// Pair slots allocated per body; a denser scene overflows and is reported (or grows,
    /// with `auto_grow`).
    pub pairs_per_body: u32,
    /// Pair slots allocated at least, so small scenes never start too tight.
    pub min_pair_capacity: u32,
    /// Let [`GpuCollision::step_and_read`] grow the pair buffers and redo the step on overflow.
    pub auto_grow: bool,
    /// Contact recycling, m: a pair whose bodies barely moved relative to each other keeps
    /// last step's manifold while its points slid at most this far (and at most
    /// `tumble_solver::RECYCLE_SIZE_FRACTION` of the pair's smallest half extent) across the
    /// normal; 0 computes every manifold afresh. The rule of `tumble_solver::CachedManifold::
    /// recycle` (docs/solver.md, "Contact recycling").
    pub recycle_distance: f32,
    /// Whether `collide_cuboids` first lists the pairs of a workgroup that need the full
    /// test and runs them on its first threads; `None` takes the device's choice
    /// ([`crate::kernels::collide_cuboids::compact_fresh_pairs`]). Both give the same bits;
    /// the choice is about speed.
    pub compact_fresh_pairs: Option<bool>,
}

impl Default for CollisionConfig {
    fn default() -> Self {
        Self {
            // The facade's default speculative margin (2 cm) and 60 Hz step.
            margin: 0.02,
            dt: 1.0 / 60.0,
            // A box in a dense pile touches about 6 neighbours (faces of a grid); 8 leaves room
            // for the extra pairs the margin and velocity sweep add.
            pairs_per_body: 8,
            min_pair_capacity: 4096,
            auto_grow: true,
            // The facade's default (`WorldConfig::recycle_distance`).
            recycle_distance: tumble_solver::DEFAULT_RECYCLE_DISTANCE,
            compact_fresh_pairs: None,
        }
    }
}

/// Pair slots added on top of what an overflow asked for when growing, as a fraction, so a
/// scene that is still getting denser does not overflow again on the next step.
const GROWTH_HEADROOM: f32 = 0.25;

/// Readback sizing: pairs copied speculatively beyond last step's count, as a fraction and
/// a floor (a second, blocking copy fetches the rest when a step has more).
const READBACK_HEADROOM: f32 = 0.25;
const READBACK_MIN_PAIRS: u32 = 1024;

/// A readback recorded into a command stream, not yet submitted.
#[derive(Debug)]
pub struct ReadbackPlan {
    slot: usize,
    request: ReadbackRequest,
    parity: usize,
    step: u64,
    copied_pairs: u32,
    copied_touching: u32,
    copied_points: u32,
    regions: Vec<Region>,
}

/// A submitted readback; turn it into data with [`GpuCollision::receive`].
#[derive(Debug)]
pub struct PendingReadback {
    ticket: Ticket,
    plan: ReadbackPlan,
}

/// The snapshot's parts, read once each out of the mapped staging buffer.
fn decode(plan: &ReadbackPlan, mapped: &Mapped<'_>) -> Result<CollisionSnapshot, GpuError> {
    let mut regions = plan.regions.iter();
    let mut next = || {
        regions
            .next()
            .copied()
            .unwrap_or(Region { offset: 0, len: 0 })
    };
    let work: Vec<WorkList> = mapped.read(&next())?;
    let mut snap = CollisionSnapshot {
        work: work.first().copied().unwrap_or_default(),
        ..Default::default()
    };
    let r = &plan.request;
    if r.pairs {
        let a: Vec<u32> = mapped.read(&next())?;
        let b: Vec<u32> = mapped.read(&next())?;
        snap.pairs = a.into_iter().zip(b).collect();
    }
    if r.manifolds {
        snap.manifolds = mapped.read(&next())?;
        snap.contacts = mapped.read(&next())?;
    }
    if r.aabbs {
        snap.aabbs = mapped.read(&next())?;
    }
    if r.touching {
        let counts: Vec<TouchingCounts> = mapped.read(&next())?;
        snap.touching_counts = counts.first().copied().unwrap_or_default();
        snap.touching.touching = mapped.read(&next())?;
        snap.touching.manifolds = mapped.read(&next())?;
        snap.touching.points = mapped.read(&next())?;
    }
    Ok(snap)
}

/// The GPU collision pipeline and its buffers.
#[derive(Debug)]
pub struct GpuCollision {
    ctx: GpuContext,
    config: CollisionConfig,
    kernels: CollisionKernels,
    radix: RadixSort,
    pool: BufferPool,
    body_count: u32,
    pair_capacity: u32,
    /// Boxes longer than this on the sweep axis are paired apart from the sweep (m).
    long_extent: f32,
    /// Bits of the largest world index, which lead the sweep's sort keys (0 for one world).
    world_bits: u32,
    /// Workgroups of the body sort by world (`sort_world_bodies`, one per world), or 0 where
    /// the step sorts its bodies as one list ([`Self::set_bodies`] decides).
    world_sort_groups: u32,
    /// Whether the step sorts its pairs by world too (`sort_world_pairs`, one workgroup per
    /// world; every world small enough that its pairs fit one rank sort).
    world_pair_sort: bool,
    groups: Option<CollisionGroups>,
    steps: u64,
    readback: Readback,
    readback_pairs: u32,
    readback_touching: u32,
    /// Manifolds and points of the last touching readback (what `store_touching_impulses`
    /// expects).
    last_touching: TouchingCounts,
    /// Times last step's pairs were dropped ([`Self::forget_history`]): kernels comparing a
    /// step with the one before (contact events) know the comparison is void when it changed.
    history_resets: u64,
    /// Whether the dense touching list is held ([`buffers::TOUCHING_BUFFERS`]: from the first
    /// readback that asks for it on).
    touching_buffers: bool,
}

impl GpuCollision {
    /// Builds the pipelines; bodies come with [`Self::set_bodies`].
    pub fn new(ctx: &GpuContext, config: CollisionConfig) -> Result<Self, GpuError> {
        validate::check_at_least("config.margin", config.margin, 0.0)?;
        validate::check_at_least("config.dt", config.dt, 0.0)?;
        validate::check_recycle_distance("config.recycle_distance", config.recycle_distance)?;
        Ok(Self {
            ctx: ctx.clone(),
            config,
            kernels: CollisionKernels::build(|spec| {
                if std::ptr::eq(spec, &COLLIDE_CUBOIDS) {
                    collide_cuboids_kernel(ctx, config.compact_fresh_pairs)
                } else {
                    Kernel::new(ctx, spec)
                }
            })?,
            radix: RadixSort::new(ctx)?,
            pool: BufferPool::new(ctx).with_per_step(&buffers::PER_STEP_BUFFERS),
            body_count: 0,
            pair_capacity: 0,
            long_extent: f32::INFINITY,
            world_bits: 0,
            world_sort_groups: 0,
            world_pair_sort: false,
            groups: None,
            steps: 0,
            readback: Readback::new(ctx),
            readback_pairs: READBACK_MIN_PAIRS,
            readback_touching: READBACK_MIN_PAIRS,
            last_touching: TouchingCounts::default(),
            history_resets: 0,
            touching_buffers: false,
        })
    }

    /// The settings.
    pub fn config(&self) -> &CollisionConfig {
        &self.config
    }

    /// Bodies uploaded.
    pub fn body_count(&self) -> u32 {
        self.body_count
    }

    /// Pair slots currently allocated.
    pub fn pair_capacity(&self) -> u32 {
        self.pair_capacity
    }

    /// Steps recorded so far.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Uploads every body. Body `i` must stay the same body from call to call for warm
    /// starting to match pairs; a different count starts without history.
    pub fn set_bodies(
        &mut self,
        poses: &[GpuPose],
        velocities: &[GpuVelocity],
        shapes: &[GpuShape],
    ) -> Result<(), GpuError> {
        self.upload(poses, velocities, shapes, None).map(|_| ())
    }

    /// [`Self::set_bodies`] keeping last step's pairs, renumbered through `remap` (one entry
    /// per body of the last upload: `remap_pairs.wgsl`). True when they were kept; false
    /// when the pair buffers had to grow, which drops every pair (as [`Self::set_bodies`]).
    pub fn set_bodies_remapped(
        &mut self,
        poses: &[GpuPose],
        velocities: &[GpuVelocity],
        shapes: &[GpuShape],
        remap: &[u32],
    ) -> Result<bool, GpuError> {
        validate::check_count("remap", remap.len(), self.body_count as usize)?;
        self.upload(poses, velocities, shapes, Some(remap))
    }

    fn upload(
        &mut self,
        poses: &[GpuPose],
        velocities: &[GpuVelocity],
        shapes: &[GpuShape],
        remap: Option<&[u32]>,
    ) -> Result<bool, GpuError> {
        let n = poses.len();
        validate::check_motion(poses, velocities, n)?;
        validate::check_count("shapes", shapes.len(), n)?;
        if n > MAX_BODIES as usize {
            return Err(GpuError::LimitExceeded {
                what: "bodies".into(),
                value: n as u64,
                limit_name: "tumble_gpu::MAX_BODIES",
                limit: MAX_BODIES.into(),
            });
        }
        validate::check_shapes(shapes)?;
        let n = n as u32;
        // The per-body guess is only a guess: never ask for more than the device can bind
        // (an actual overflow still grows, and errs only if the real count does not fit).
        let wanted = n
            .saturating_mul(self.config.pairs_per_body)
            .max(self.config.min_pair_capacity)
            .min(self.max_pairs())
            .max(self.pair_capacity);
        self.long_extent = crate::kernels::sweep_pairs::long_extent(shapes);
        // Worlds are in increasing order (checked above): the last body's is the largest.
        let last_world = shapes.last().map_or(0, |s| s.flags >> BODY_WORLD_SHIFT);
        self.world_bits = u32::BITS - last_world.leading_zeros();
        let kept = self.allocate(n, wanted, remap.is_some())?;
        if kept && let Some(remap) = remap {
            self.remap_pairs(remap)?;
        }
        self.world_sort_groups = self.plan_world_sort(shapes)?;
        self.write_motion(poses, velocities);
        let queue = &self.ctx.queue;
        queue.write_buffer(self.pool.get(SHAPES), 0, bytemuck::cast_slice(shapes));
        let groups = vec![GpuCollisionGroups::ALL; n as usize];
        queue.write_buffer(self.pool.get(GROUPS), 0, bytemuck::cast_slice(&groups));
        Ok(kept)
    }

    /// Sets the collision groups of bodies `first..first + groups.len()` (every body has
    /// [`GpuCollisionGroups::ALL`] after [`Self::set_bodies`]); the broad phase forms no pair
    /// whose groups do not interact, from the next recorded step on.
    pub fn set_groups(
        &mut self,
        first: usize,
        groups: &[GpuCollisionGroups],
    ) -> Result<(), GpuError> {
        let n = self.body_count as usize;
        if first.checked_add(groups.len()).is_none_or(|end| end > n) {
            return Err(GpuError::InvalidInput {
                field: "groups".into(),
                value: format!("bodies {first}..+{} of {n}", groups.len()),
            });
        }
        let offset = (first * std::mem::size_of::<GpuCollisionGroups>()) as u64;
        self.ctx
            .queue
            .write_buffer(self.pool.get(GROUPS), offset, bytemuck::cast_slice(groups));
        Ok(())
    }

    /// Uploads new poses and velocities for the same bodies (shapes unchanged).
    pub fn set_motion(
        &mut self,
        poses: &[GpuPose],
        velocities: &[GpuVelocity],
    ) -> Result<(), GpuError> {
        validate::check_motion(poses, velocities, self.body_count as usize)?;
        self.write_motion(poses, velocities);
        Ok(())
    }

    fn write_motion(&self, poses: &[GpuPose], velocities: &[GpuVelocity]) {
        let queue = &self.ctx.queue;
        queue.write_buffer(self.pool.get(POSES), 0, bytemuck::cast_slice(poses));
        let velocities = bytemuck::cast_slice(velocities);
        queue.write_buffer(self.pool.get(VELOCITIES), 0, velocities);
    }

    /// Sizes every buffer for `bodies` bodies and `capacity` pairs and writes the parameters.
    /// Unless `keep_pairs`, a new body count drops last step's pairs; pair buffers that had
    /// to grow drop them either way. True when they were kept.
    fn allocate(&mut self, bodies: u32, capacity: u32, keep_pairs: bool) -> Result<bool, GpuError> {
        // The largest buffer first, so a refused size leaves every buffer as it was.
        let contact_bytes = u64::from(capacity)
            * u64::from(MAX_MANIFOLD_POINTS)
            * std::mem::size_of::<GpuContact>() as u64;
        self.ctx.check_storage_size(CONTACTS[0], contact_bytes)?;
        let mut reset = bodies != self.body_count && !keep_pairs;
        reset |= ensure_body_buffers(&mut self.pool, bodies)? && !keep_pairs;
        reset |= ensure_pair_buffers(&mut self.pool, capacity)?;
        if self.touching_buffers {
            ensure_touching_buffers(&mut self.pool, capacity)?;
        }
        self.body_count = bodies;
        self.pair_capacity = capacity;
        let queue = &self.ctx.queue;
        let c = &self.config;
        let write =
            |name: &'static str, bytes: &[u8]| queue.write_buffer(self.pool.get(name), 0, bytes);
        write(BODY_WORK, bytemuck::bytes_of(&WorkList::for_count(bodies)));
        write(
            UPDATE_PARAMS,
            bytemuck::bytes_of(&UpdateAabbsParams {
                count: bodies,
                margin: c.margin,
                dt: c.dt,
                _pad: 0,
            }),
        );
        write(
            SWEEP_PARAMS,
            bytemuck::bytes_of(&SweepParams {
                body_count: bodies,
                pair_capacity: capacity,
                long_extent: self.long_extent,
                world_bits: self.world_bits,
            }),
        );
        write(
            NARROW_PARAMS,
            bytemuck::bytes_of(&NarrowParams {
                margin: c.margin,
                dt: c.dt,
                recycle_distance: c.recycle_distance,
                ..Default::default()
            }),
        );
        if reset {
            self.forget_history();
        }
        Ok(!reset)
    }

    /// Drops last step's pairs, so the next step carries no impulses and no hysteresis (for
    /// when body indices were reassigned).
    pub fn forget_history(&mut self) {
        self.history_resets += 1;
        let empty = WorkList {
            capacity: self.pair_capacity,
            ..Default::default()
        };
        for name in PAIR_WORK {
            self.ctx
                .queue
                .write_buffer(self.pool.get(name), 0, bytemuck::bytes_of(&empty));
        }
    }

    /// The most pair slots this device can bind (the contact buffer, four points of 48 bytes
    /// per slot, is the largest).
    pub fn max_pairs(&self) -> u32 {
        let limits = self.ctx.limits();
        let bytes = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        let per_pair = u64::from(MAX_MANIFOLD_POINTS) * std::mem::size_of::<GpuContact>() as u64;
        (bytes / per_pair).min(u64::from(u32::MAX)) as u32
    }

    /// Makes room for at least `capacity` pairs (history is dropped if buffers move).
    pub fn reserve_pairs(&mut self, capacity: u32) -> Result<(), GpuError> {
        if capacity > self.pair_capacity {
            self.allocate(self.body_count, capacity, false)?;
        }
        Ok(())
    }

    fn ensure_groups(&mut self) {
        let fresh = self.groups.as_ref().is_some_and(|g| {
            g.generation == self.pool.generation()
                && g.pair_bits == crate::kernels::radix_sort::index_bits(self.body_count)
        });
        if !fresh {
            self.groups = Some(build_groups(
                &self.ctx,
                &self.kernels,
                &self.radix,
                &self.pool,
                self.body_count,
            ));
        }
    }

    /// The parity (pair set) of the last recorded step.
    fn last_parity(&self) -> usize {
        (self.steps.wrapping_sub(1) % 2) as usize
    }

    /// Records the three collision stages in compute passes named by this module's timer
    /// names (timed when `timer` has timestamps). Nothing is read back; dispatch sizes that depend on the pair count
    /// are read by the GPU from the pair work list.
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut StageTimer,
    ) -> Result<(), GpuError> {
        if self.body_count == 0 {
            return Err(GpuError::InvalidInput {
                field: "bodies".into(),
                value: "none uploaded (call set_bodies first)".into(),
            });
        }
        self.ensure_groups();
        let g = self.groups.as_ref().expect("built above");
        let k = &self.kernels;
        let p = (self.steps % 2) as usize;
        let n = self.body_count;
        let pair_work = self.pool.get(PAIR_WORK[p]);
        encoder.clear_buffer(self.pool.get(PAIR_COUNTER), 0, None);
        encoder.clear_buffer(self.pool.get(LONG_BOXES), 0, Some(4));
        {
            let mut pass = timer.begin_pass(encoder, UPDATE_AABBS);
            k.update_aabbs.dispatch(&mut pass, &g.update_aabbs, n);
        }
        // The broad phase in three passes, so timestamps separate its sorts from its sweep.
        {
            let mut pass = timer.begin_pass(encoder, BROAD_PHASE_SORT_BODIES);
            k.choose_axis
                .dispatch_workgroups(&mut pass, &g.choose_axis, 1, 1);
            k.write_sort_keys.dispatch(&mut pass, &g.write_sort_keys, n);
            self.record_body_sort(&mut pass, g);
        }
        {
            let mut pass = timer.begin_pass(encoder, BROAD_PHASE_SWEEP);
            k.gather_sweep_boxes
                .dispatch(&mut pass, &g.gather_sweep_boxes, n);
            k.sweep_pairs.dispatch(&mut pass, &g.parity[p].sweep, n);
            k.long_pairs.dispatch(&mut pass, &g.parity[p].long_pairs, n);
            k.plan_dispatch
                .dispatch_workgroups(&mut pass, &g.parity[p].plan, 1, 1);
        }
        self.record_pair_sort(encoder, timer, g, p);
        {
            let mut pass = timer.begin_pass(encoder, NARROW_PHASE);
            let groups = &g.parity[p];
            k.match_pairs
                .dispatch_work(&mut pass, &groups.match_pairs, pair_work);
            k.collide_cuboids
                .dispatch_work(&mut pass, &groups.collide, pair_work);
            k.carry_impulses
                .dispatch_work(&mut pass, &groups.carry, pair_work);
        }
        self.steps += 1;
        Ok(())
    }

    /// Records and submits one step (no readback).
    pub fn step(&mut self) -> Result<(), GpuError> {
        let mut encoder = self.ctx.encoder("collision step");
        self.record(&mut encoder, &mut StageTimer::disabled(&self.ctx))?;
        self.ctx.submit(encoder)?;
        Ok(())
    }

    /// The buffers of the last recorded step beside the world's `bodies`, for the stages
    /// recorded after it.
    pub fn buffers<'a>(&'a self, bodies: &'a wgpu::Buffer) -> StepBuffers<'a> {
        step_buffers(&self.pool, self.last_parity(), bodies)
    }

    /// The pair sets of the last recorded step (`[0]`) and of the step before it (`[1]`):
    /// each its pair `WorkList`, manifolds and points, for kernels recorded after the step.
    pub fn pair_sets(&self) -> [[&wgpu::Buffer; 3]; 2] {
        let p = self.last_parity();
        let set = |p: usize| {
            [
                self.pool.get(PAIR_WORK[p]),
                self.pool.get(MANIFOLDS[p]),
                self.pool.get(CONTACTS[p]),
            ]
        };
        [set(p), set(1 - p)]
    }

    /// Times last step's pairs were dropped so far (see [`Self::forget_history`]).
    pub fn history_resets(&self) -> u64 {
        self.history_resets
    }

    /// The last recorded step's contact points (`array<GpuContact>`).
    pub fn contacts(&self) -> &wgpu::Buffer {
        self.pool.get(CONTACTS[self.last_parity()])
    }

    /// Bytes of the stage's pooled device buffers (for memory reports).
    pub fn buffer_bytes(&self) -> u64 {
        self.pool.bytes()
    }

    /// The stage's pooled device buffers by name, with their sizes in bytes.
    pub fn buffer_sizes(&self) -> Vec<(&'static str, u64)> {
        self.pool.sizes()
    }
}
