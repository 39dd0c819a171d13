//! Visiting constraints in solve order: batches run one after another; a parallel batch (one
//! graph color) spreads its constraints over the rayon pool's workers, a sequential batch (the
//! reference order, or the overflow set) runs one constraint at a time.
//!
//! The workers start once per sweep (one pass over every batch) and take blocks of [`BLOCK`]
//! constraints of the current batch by atomic counters, as Box2D v3's solver stages do; each worker
//! takes the blocks of its own contiguous share of the batch first, then helps with the others'
//! ([`Stage::claim`]). A color solved by the lane kernels is taken as `BLOCK / LANES` lane blocks
//! at a time: a block gathers its lanes' body states, solves them side by side and scatters the
//! dynamic ones back; a scalar constraint copies its two body states and writes the dynamic ones
//! back. Either way the writes go straight into the shared state array, with no scratch copy and no
//! serial write-back. Inside a color no dynamic body appears twice ([`Batch::parallel`] promises it
//! and [`check_disjoint`] checks it once per step), so a constraint reads exactly the state a
//! sequential visit would read and writes bodies no other constraint of the color reads or writes:
//! the result is the same bits on any number of threads and under any scheduling.

use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::lanes::{LANES, LaneBlock, LaneBodies};
use crate::{BodyState, ContactConstraint, Mat3};

/// Constraints per block of a parallel batch: enough work (a few microseconds) to pay for a
/// worker taking it, small enough that a color of a few hundred constraints still spreads.
pub(crate) const BLOCK: usize = 32;

// A parallel lane batch is claimed `BLOCK / LANES` lane blocks at a time.
const _: () = assert!(LANES <= BLOCK && BLOCK.is_multiple_of(LANES));

/// A run of constraints visited as one unit.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Batch {
    /// The batch's places in the solve order (indices into the step's order of contacts).
    pub range: Range<usize>,
    /// True when no two constraints of the batch share a dynamic body and it is large enough
    /// to be worth the thread pool.
    pub parallel: bool,
    /// The batch is one graph color (not the overflow set, not the sequential order): its
    /// constraints should share no dynamic body, which the step checks before relying on it.
    pub color: bool,
    /// The batch's constraints packed [`LANES`] to a block (indices into the step's lane
    /// blocks), when no two of them share a dynamic body and the solve runs the lane kernels;
    /// empty when the batch runs the scalar kernels one constraint at a time.
    pub lanes: Range<usize>,
    /// The batch's constraints as scalar constraints (indices into the step's scalar
    /// constraints): all of them when `lanes` is empty; for a sequential lane batch, the few
    /// past its last full block (the end of `range`), visited after the blocks; empty for a
    /// parallel lane batch.
    pub scalar: Range<usize>,
}

/// The instructions the lane kernels run on. Both give the same bits: the same IEEE operations
/// in the same order, on wider registers (Rust never fuses a multiply and an add on its own).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Isa {
    /// What the build targets (SSE2 on x86-64, NEON on aarch64).
    Portable,
    /// AVX2, detected at run time on x86-64.
    Avx2,
}

/// Whether the processor runs AVX2 (never off x86-64).
#[inline]
pub(crate) fn avx2_present() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

impl Isa {
    /// AVX2 where the processor has it (the lanes do not use AVX-512's wider registers),
    /// the portable path otherwise.
    pub(crate) fn detect() -> Isa {
        if avx2_present() {
            Isa::Avx2
        } else {
            Isa::Portable
        }
    }
}

/// One kind of pass over the constraints, as a scalar kernel (one constraint) and as a lane
/// kernel (a block of [`LANES`] constraints of one color), which give the same bits.
pub(crate) trait Pass: Sync {
    /// The pass on one constraint and copies of its two bodies.
    fn scalar(&self, c: &mut ContactConstraint, a: &mut BodyState, b: &mut BodyState);
    /// The pass on a block and its bodies' lanes.
    fn lanes(&self, c: &mut LaneBlock, bodies: &mut LaneBodies);
}

/// What a sweep visits: the step's scalar constraints and lane blocks, the batches over them,
/// the bodies' world inverse inertias (read only, gathered with the velocities), and the
/// instructions the lane kernels run on.
pub(crate) struct SweepSet<'a> {
    pub(crate) constraints: &'a mut [ContactConstraint],
    pub(crate) blocks: &'a mut [LaneBlock],
    pub(crate) batches: &'a [Batch],
    pub(crate) inverse_inertia: &'a [Mat3],
    pub(crate) isa: Isa,
}

/// Applies `pass` to every constraint of `set`, batch by batch: a batch with lane blocks through the
/// lane kernel, block by block, any other through the scalar kernel, constraint by constraint.
///
/// Every batch marked parallel or packed into lanes must have no dynamic body twice (as
/// [`check_disjoint`] says). With one thread, or no parallel batch, the batches run in order on the
/// calling thread. Otherwise the pool's workers start once for the whole sweep: each batch is a
/// stage of blocks (a parallel batch [`BLOCK`] constraints per block, a sequential one a single
/// block), a worker claims a block of the current stage (from its own share first:
/// [`Stage::claim`]) and solves it in place, and moves to the next stage once every block of this
/// one is done. A worker that starts late finds the finished stages' blocks all claimed and catches
/// up, so the sweep never waits for a worker that the pool has not started, and the calling thread
/// alone can finish it.
pub(crate) fn sweep<P: Pass>(set: &mut SweepSet<'_>, states: &mut [BodyState], pass: &P) {
    let SweepSet {
        constraints,
        blocks,
        batches,
        inverse_inertia,
        isa,
    } = set;
    let (batches, inverse_inertia, isa) = (*batches, *inverse_inertia, *isa);
    assert_eq!(
        inverse_inertia.len(),
        states.len(),
        "one inverse inertia per body"
    );
    assert!(
        batches
            .iter()
            .all(|b| b.scalar.end <= constraints.len() && b.lanes.end <= blocks.len()),
        "batch out of range"
    );
    let shared = Shared {
        constraints: constraints.as_mut_ptr(),
        blocks: blocks.as_mut_ptr(),
        states: states.as_mut_ptr(),
        inverse_inertia: inverse_inertia.as_ptr(),
        len: states.len(),
    };
    let threads = rayon::current_num_threads();
    let wide = batches.iter().any(|b| b.parallel && b.range.len() > BLOCK);
    if threads == 1 || !wide {
        for batch in batches {
            // SAFETY: one thread; the ranges are in bounds (checked above); a lane batch's
            // constraints share no dynamic body (the caller's contract).
            unsafe { shared.solve_batch(batch, 0..batch_items(batch), pass, isa) };
        }
        return;
    }
    let stages: Vec<Stage> = batches
        .iter()
        .map(|b| {
            let items = batch_items(b);
            let per_block = match (b.parallel, b.lanes.is_empty()) {
                (true, true) => BLOCK,
                (true, false) => BLOCK / LANES,
                (false, _) => items.max(1),
            };
            Stage::new(items, per_block, threads)
        })
        .collect();
    // Worker `w` starts each stage in its own share: a color's constraints come in pair order,
    // so a worker keeps to about the same bodies from color to color and finds their states
    // in its own cache.
    let work = |w: usize| {
        for (stage, batch) in stages.iter().zip(batches) {
            let blocks = stage.blocks;
            while let Some(k) = stage.claim(w) {
                let from = k * stage.block;
                let to = (from + stage.block).min(stage.items);
                // SAFETY: blocks of a stage are disjoint runs of the batch (in range, checked
                // above), each claimed by exactly one worker; the stage's dynamic bodies are
                // disjoint between its blocks (a parallel batch's contract; a sequential
                // batch is one block), and no other stage runs meanwhile: a worker enters
                // the next stage only after every block of this one is done.
                unsafe { shared.solve_batch(batch, from..to, pass, isa) };
                stage.done.fetch_add(1, Ordering::Release);
            }
            // Every block is claimed: wait for the ones still being solved, whose writes
            // the next stage reads (the acquire pairs with each block's release).
            let mut spins = 0u32;
            while stage.done.load(Ordering::Acquire) < blocks {
                spins += 1;
                if spins < 64 {
                    std::hint::spin_loop();
                } else {
                    std::thread::yield_now();
                }
            }
        }
    };
    let work = &work;
    rayon::scope(|scope| {
        for w in 1..threads {
            scope.spawn(move |_| work(w));
        }
        work(0);
    });
}

/// The units a batch is visited in: its lane blocks (a sequential lane batch's scalar tail
/// comes with the last unit), or its constraints.
fn batch_items(batch: &Batch) -> usize {
    if batch.lanes.is_empty() {
        batch.scalar.len()
    } else {
        batch.lanes.len()
    }
}

/// First block of share `s` when `blocks` blocks are cut into `shares` contiguous shares.
fn share_start(blocks: usize, shares: usize, s: usize) -> usize {
    s * blocks / shares
}

/// A claim counter on a cache line of its own (two lines: adjacent-line prefetch), so that the
/// workers' counters do not share one.
#[repr(align(128))]
struct Counter(AtomicUsize);

/// One stage of a staged sweep: a batch cut into blocks of `block` items (constraints or lane
/// blocks), the blocks cut into one contiguous share per worker, with a claim counter per
/// share and the stage's done counter.
struct Stage {
    items: usize,
    block: usize,
    /// Blocks of the stage.
    blocks: usize,
    /// Per share, the next block to claim (share `s` holds blocks `share_start(s)..share_start(s
    /// + 1)`).
    next: Vec<Counter>,
    done: AtomicUsize,
}

impl Stage {
    /// `items` cut into blocks of `block`, the blocks into `workers` shares.
    fn new(items: usize, block: usize, workers: usize) -> Self {
        let blocks = items.div_ceil(block);
        Self {
            items,
            block,
            blocks,
            next: (0..workers)
                .map(|s| Counter(AtomicUsize::new(share_start(blocks, workers, s))))
                .collect(),
            done: AtomicUsize::new(0),
        }
    }

    /// First block of share `s` (of `self.next.len()`).
    fn share_start(&self, s: usize) -> usize {
        share_start(self.blocks, self.next.len(), s)
    }

    /// Claims a block for worker `w`: the next of its own share, then of the shares after
    /// it in turn (a worker that finished its share helps the others, and one that started
    /// late finds its share taken). `None` once every block is claimed.
    fn claim(&self, w: usize) -> Option<usize> {
        let shares = self.next.len();
        for k in 0..shares {
            let s = (w + k) % shares;
            let end = self.share_start(s + 1);
            if self.next[s].0.load(Ordering::Relaxed) >= end {
                continue;
            }
            let b = self.next[s].0.fetch_add(1, Ordering::Relaxed);
            if b < end {
                return Some(b);
            }
        }
        None
    }
}

/// The constraint, lane block and state arrays shared by the workers of a staged sweep.
#[derive(Clone, Copy)]
struct Shared {
    constraints: *mut ContactConstraint,
    blocks: *mut LaneBlock,
    states: *mut BodyState,
    /// The bodies' world inverse inertias, `len` of them (read only).
    inverse_inertia: *const Mat3,
    len: usize,
}

// SAFETY: the pointers are only dereferenced inside `sweep`, while the slices they were made
// from are mutably borrowed by it; which worker touches which element is said at each use.
unsafe impl Send for Shared {}
// SAFETY: as above.
unsafe impl Sync for Shared {}

impl Shared {
    /// Solves lane blocks `blocks` in order, in place: each block's bodies gathered into
    /// lanes, the pass's lane kernel, the dynamic bodies' velocities scattered back.
    ///
    /// # Safety
    /// As [`Shared::solve_batch`], for a lane batch.
    #[inline(always)]
    unsafe fn solve_blocks<P: Pass, const AVX2: bool>(self, blocks: Range<usize>, pass: &P) {
        for i in blocks {
            // SAFETY: the caller's contract: block `i` is this thread's alone.
            let block = unsafe { &mut *self.blocks.add(i) };
            // SAFETY: `gather` checks every body index against the states' length (the
            // inverse inertias' too, asserted by `sweep`); the bodies it reads are written by
            // no other thread meanwhile.
            let mut bodies = unsafe {
                #[cfg(target_arch = "x86_64")]
                if AVX2 {
                    // SAFETY: as `gather`, and AVX2 is present (`AVX2` is set only by
                    // `solve_blocks_avx2`, whose callers check it).
                    block.gather_avx2(self.states, self.inverse_inertia, self.len)
                } else {
                    block.gather(self.states, self.inverse_inertia, self.len)
                }
                #[cfg(not(target_arch = "x86_64"))]
                block.gather(self.states, self.inverse_inertia, self.len)
            };
            pass.lanes(block, &mut bodies);
            // SAFETY: indices checked by `gather`; the dynamic bodies are this block's.
            unsafe { block.scatter(&bodies, self.states) };
        }
    }

    /// [`Shared::solve_blocks`] compiled for AVX2: the same operations, on 256-bit registers.
    ///
    /// # Safety
    /// The processor has AVX2, and [`Shared::solve_blocks`]'s contract.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn solve_blocks_avx2<P: Pass>(self, blocks: Range<usize>, pass: &P) {
        // SAFETY: the caller's contract.
        unsafe { self.solve_blocks::<P, true>(blocks, pass) }
    }

    /// No AVX2 off x86-64: the portable blocks.
    ///
    /// # Safety
    /// [`Shared::solve_blocks`]'s contract.
    #[cfg(not(target_arch = "x86_64"))]
    unsafe fn solve_blocks_avx2<P: Pass>(self, blocks: Range<usize>, pass: &P) {
        // SAFETY: the caller's contract.
        unsafe { self.solve_blocks::<P, false>(blocks, pass) }
    }

    /// Solves items `items` of `batch` (lane blocks, then a sequential lane batch's scalar
    /// tail, which is visited as one unit with all its blocks; or constraints) in order, in
    /// place.
    ///
    /// # Safety
    /// The batch's ranges lie inside the arrays; no other thread touches these items, writes
    /// any body they read, or reads or writes a dynamic body of theirs meanwhile; a lane
    /// batch's constraints share no dynamic body.
    unsafe fn solve_batch<P: Pass>(self, batch: &Batch, items: Range<usize>, pass: &P, isa: Isa) {
        let mut items = items;
        if !batch.lanes.is_empty() {
            let blocks = batch.lanes.start + items.start..batch.lanes.start + items.end;
            match isa {
                // SAFETY: AVX2 is present (checked here: `Isa::Avx2` is any crate code's to
                // build; the detection is a cached load); the rest is the caller's contract.
                Isa::Avx2 if avx2_present() => unsafe { self.solve_blocks_avx2(blocks, pass) },
                // SAFETY: the caller's contract.
                Isa::Avx2 | Isa::Portable => unsafe { self.solve_blocks::<P, false>(blocks, pass) },
            }
            // A sequential lane batch's scalar tail follows its blocks (a sequential batch is
            // visited as one unit; a parallel lane batch has no tail).
            if batch.scalar.is_empty() {
                return;
            }
            debug_assert!(!batch.parallel, "a parallel lane batch has no scalar tail");
            items = 0..batch.scalar.len();
        }
        for i in items {
            // SAFETY: the caller's contract: constraint `i` is this thread's alone.
            let c = unsafe { &mut *self.constraints.add(batch.scalar.start + i) };
            let (ia, ib) = (c.body_a as usize, c.body_b as usize);
            assert!(ia < self.len && ib < self.len, "body index out of range");
            // SAFETY: in range (checked); no other thread writes these bodies meanwhile.
            let (mut a, mut b) = unsafe { (*self.states.add(ia), *self.states.add(ib)) };
            pass.scalar(c, &mut a, &mut b);
            // SAFETY: a dynamic body of this constraint is no other thread's meanwhile.
            unsafe {
                if c.dynamic_a {
                    set_velocities(&mut *self.states.add(ia), &a);
                }
                if c.dynamic_b {
                    set_velocities(&mut *self.states.add(ib), &b);
                }
            }
        }
    }
}

/// True when no dynamic body appears in two of the constraints whose two bodies (index, and
/// whether it is dynamic) `ends` lists: the condition for visiting them as one parallel batch
/// or side by side in lanes. `stamps` (one entry per body, any contents) is scratch space,
/// `stamp` a value not yet written into it for this batch.
pub(crate) fn check_disjoint(
    ends: impl IntoIterator<Item = [(u32, bool); 2]>,
    stamps: &mut [u32],
    stamp: u32,
) -> bool {
    for pair in ends {
        for (body, dynamic) in pair {
            if !dynamic {
                continue;
            }
            match stamps.get_mut(body as usize) {
                Some(s) if *s != stamp => *s = stamp,
                _ => return false,
            }
        }
    }
    true
}

/// Stores the solved velocities of a dynamic body (its deltas are not the passes' to change).
#[inline]
fn set_velocities(out: &mut BodyState, solved: &BodyState) {
    out.linear_velocity = solved.linear_velocity;
    out.angular_velocity = solved.angular_velocity;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ConstraintPoint, Mat3, Softness};
    use tumble_geometry::{MAX_MANIFOLD_POINTS, Vec3};

    /// A constraint between `a` and `b` (index, dynamic); only the bodies matter here.
    fn between(a: (u32, bool), b: (u32, bool)) -> ContactConstraint {
        ContactConstraint {
            body_a: a.0,
            body_b: b.0,
            contact: 0,
            dynamic_a: a.1,
            dynamic_b: b.1,
            normal: Vec3::y(),
            tangent1: Vec3::x(),
            tangent2: Vec3::z(),
            inverse_mass_a: Vec3::zeros(),
            inverse_mass_b: Vec3::zeros(),
            inverse_inertia_a: Mat3::zeros(),
            inverse_inertia_b: Mat3::zeros(),
            friction: 0.0,
            restitution: 0.0,
            softness: Softness::default(),
            slop: 0.0,
            point_count: 0,
            points: [ConstraintPoint::default(); MAX_MANIFOLD_POINTS],
            patch_radius: 0.0,
            tilt_mass: [0.0; 2],
            tilt_impulse: [0.0; 2],
            tilt_push_a: [Vec3::zeros(); 2],
            tilt_push_b: [Vec3::zeros(); 2],
        }
    }

    /// The two bodies of each constraint, as the batch check reads them.
    fn ends(cs: &[ContactConstraint]) -> Vec<[(u32, bool); 2]> {
        cs.iter()
            .map(|c| [(c.body_a, c.dynamic_a), (c.body_b, c.dynamic_b)])
            .collect()
    }

    #[test]
    fn a_batch_is_disjoint_unless_a_dynamic_body_repeats() {
        let mut stamps = vec![u32::MAX; 4];
        // Body 0 is fixed and shared: allowed, it is only read.
        let shared_floor = [
            between((0, false), (1, true)),
            between((0, false), (2, true)),
        ];
        assert!(check_disjoint(ends(&shared_floor), &mut stamps, 0));
        // Body 2 is dynamic in two constraints: in place, their writes would race.
        let shared_box = [between((1, true), (2, true)), between((2, true), (3, true))];
        assert!(!check_disjoint(ends(&shared_box), &mut stamps, 1));
        // A body index past the state array is refused, not read.
        assert!(!check_disjoint(
            ends(&[between((0, false), (9, true))]),
            &mut stamps,
            2
        ));
    }

    /// A stage of `blocks` blocks of one item for `workers` workers.
    fn stage(blocks: usize, workers: usize) -> Stage {
        Stage::new(blocks, 1, workers)
    }

    #[test]
    fn each_worker_starts_in_its_own_share_and_every_block_is_claimed_once() {
        // 10 blocks for 3 workers: shares 0..3, 3..6, 6..10.
        let s = stage(10, 3);
        assert_eq!(
            s.claim(1),
            Some(3),
            "worker 1 starts at its share's first block"
        );
        assert_eq!(s.claim(2), Some(6));
        assert_eq!(s.claim(0), Some(0));
        assert_eq!(s.claim(1), Some(4), "and keeps to its share");
        // Worker 2 alone now takes what is left: its share first, then the others' in turn
        // (as a worker that finished its share does, or one left alone while the others
        // have not started).
        let mut rest = Vec::new();
        while let Some(b) = s.claim(2) {
            rest.push(b);
        }
        assert_eq!(rest, vec![7, 8, 9, 1, 2, 5]);
        assert_eq!(s.claim(0), None, "every block was claimed");
        // Blocks fewer than workers: empty shares are skipped, each block once.
        let s = stage(2, 4);
        let mut got: Vec<usize> = (0..4).filter_map(|w| s.claim(w)).collect();
        got.sort_unstable();
        assert_eq!(got, vec![0, 1]);
        assert!((0..4).all(|w| s.claim(w).is_none()));
        // No block: nothing to claim.
        assert_eq!(stage(0, 2).claim(1), None);
    }

    #[test]
    fn workers_claiming_at_once_take_every_block_exactly_once() {
        // Eight threads claim from one stage at the same time, as the sweep's workers do: a
        // claim that is not atomic, or one that hands out a block past its share's end, would
        // give some block twice or lose one. 1,000 rounds of 37 blocks (shares of 4 and 5).
        for _ in 0..1000 {
            let s = stage(37, 8);
            let claimed: Vec<Vec<usize>> = std::thread::scope(|scope| {
                let handles: Vec<_> = (0..8)
                    .map(|w| {
                        let s = &s;
                        scope.spawn(move || std::iter::from_fn(|| s.claim(w)).collect())
                    })
                    .collect();
                handles.into_iter().map(|h| h.join().unwrap()).collect()
            });
            let mut all: Vec<usize> = claimed.concat();
            all.sort_unstable();
            assert_eq!(all, (0..37).collect::<Vec<_>>());
            // Each worker's own claims come in order within each share.
            for own in &claimed {
                for pair in own.windows(2) {
                    let share = |b: usize| (0..8).rposition(|t| share_start(37, 8, t) <= b);
                    if share(pair[0]) == share(pair[1]) {
                        assert!(pair[0] < pair[1], "{own:?}");
                    }
                }
            }
        }
    }
}
