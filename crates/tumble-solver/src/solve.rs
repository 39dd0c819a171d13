//! The solve stage: from bodies and manifolds to new velocities and in-step deltas.
//!
//! Soft step (Box2D v3, `b2SolverStage_*`): prepare contacts once, then per substep integrate
//! velocities, warm start, solve (biased), integrate positions, relax (unbiased); after the
//! substeps apply restitution (only when a material has it) and store impulses.
//! Baumgarte (the thesis's PGS) runs the same stages with rigid rows, the bias
//! `-beta / h * max(depth - slop, 0)`, `iterations` passes and, by default, one substep and
//! no relax pass.

use rayon::prelude::*;
use tumble_geometry::{Real, Vec3};

use crate::lanes::{self, LANES, LaneBlock, LaneBodies, PrepareSource};
use crate::sweep::{Batch, Isa, Pass, SweepSet, check_disjoint, sweep};
use crate::{
    Body, BodyState, Coloring, Contact, ContactConstraint, Effects, Mat3, OVERFLOW_COLOR,
    PassContext, PrepareContext, SolveKernel, SolveOrder, SolverConfig, begin_step,
    integrate_positions, integrate_velocities_with, prepare_contact, restitution_contact,
    solve_contact, warm_start_contact,
};

/// Constraint preparation goes wide from this many manifolds (below, the pool costs more).
pub(crate) const PARALLEL_PREPARE_MIN: usize = 512;

/// Contacts per rayon task when the solved impulses are written back in parallel.
const STORE_PER_TASK: usize = 1024;

/// `SolveBuffers::source` of a contact no constraint solved.
const NO_SOURCE: u32 = u32::MAX;

/// `SolveBuffers::source` bit of a contact solved by a scalar constraint (the rest is its
/// index among the scalar constraints); without it, the entry is `block * LANES + lane`.
const SCALAR_SOURCE: u32 = 1 << 31;

/// What one solve did, for statistics.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SolveStats {
    /// Constraints solved (one per manifold).
    pub constraints: usize,
    /// Contact points solved.
    pub points: usize,
    /// Batches that ran on the thread pool.
    pub parallel_batches: usize,
}

/// What the solve stage keeps between steps so that a step allocates nothing once the scene's
/// size has been reached: the constraints (about 1 KB each, megabytes on a large pile), their
/// lane blocks, the bodies' world inverse inertias, the visiting order and its batches, and
/// the scratch of the batch check. Holding one across steps changes no result: every buffer
/// is rewritten in full before it is read.
#[derive(Debug, Default)]
pub struct SolveBuffers {
    constraints: Vec<ContactConstraint>,
    blocks: Vec<LaneBlock>,
    inverse_inertia: Vec<Mat3>,
    order: Vec<u32>,
    batches: Vec<Batch>,
    stamps: Vec<u32>,
    /// Per contact, the constraint or lane its impulses are stored from (parallel store).
    source: Vec<u32>,
}

/// The warm start: each constraint's stored impulses applied again.
struct WarmStart;

impl Pass for WarmStart {
    fn scalar(&self, c: &mut ContactConstraint, a: &mut BodyState, b: &mut BodyState) {
        warm_start_contact(c, a, b);
    }
    #[inline(always)]
    fn lanes(&self, c: &mut LaneBlock, bodies: &mut LaneBodies) {
        lanes::warm_start(c, bodies);
    }
}

/// A biased or relax pass.
struct Velocity(PassContext);

impl Pass for Velocity {
    fn scalar(&self, c: &mut ContactConstraint, a: &mut BodyState, b: &mut BodyState) {
        solve_contact(c, a, b, &self.0);
    }
    #[inline(always)]
    fn lanes(&self, c: &mut LaneBlock, bodies: &mut LaneBodies) {
        lanes::solve(c, bodies, &self.0);
    }
}

/// The restitution pass after the substeps, with its approach-speed threshold.
struct Restitution(Real);

impl Pass for Restitution {
    fn scalar(&self, c: &mut ContactConstraint, a: &mut BodyState, b: &mut BodyState) {
        restitution_contact(c, a, b, self.0);
    }
    #[inline(always)]
    fn lanes(&self, c: &mut LaneBlock, bodies: &mut LaneBodies) {
        lanes::restitution(c, bodies, self.0);
    }
}

/// Most constraints at the end of a sequential lane batch that the scalar kernel visits instead
/// of a last lane block (of at least five padding lanes).
const SCALAR_TAIL: usize = 3;

/// The fewest and the most lane blocks per task of the prepare on the pool: a run of a few
/// blocks is what the prefetches run ahead in; a color of the pyramid of 12 (about 27
/// blocks) still spreads over two threads.
const PREPARE_MIN_RUN: usize = 4;
const PREPARE_MAX_RUN: usize = 32;

/// Fills `out` with the lane blocks of the constraints `indices`, [`LANES`] per block in
/// order. The contacts are read in color order, all over the array, where the hardware's
/// prefetcher cannot follow: each block first asks for the contacts of the block two ahead
/// and for the bodies of the next one (whose contacts were asked for a block earlier). On
/// the 4,901-cube pyramid this took the prepare from 9.6-10.4 to 6.8-7.6 ms a step on one
/// thread (docs/benchmarks.md); the blocks are the same bits.
fn prepare_blocks(out: &mut [LaneBlock], indices: &[u32], inputs: &PrepareSource<'_>, isa: Isa) {
    let block = |k: usize| {
        let start = k * LANES;
        (start < indices.len()).then(|| &indices[start..(start + LANES).min(indices.len())])
    };
    for (k, b) in out.iter_mut().enumerate() {
        if let Some(ahead) = block(k + 2) {
            crate::lanes::prefetch_block(ahead, inputs, false);
        }
        if let Some(next) = block(k + 1) {
            crate::lanes::prefetch_block(next, inputs, true);
        }
        if let Some(indices) = block(k) {
            b.prepare(indices, inputs, isa);
        }
    }
}

/// The visiting order: the constraint permutation (`order`) and its batches.
fn plan(
    contacts: &[Contact],
    coloring: &Coloring,
    config: &SolverConfig,
    order: &mut Vec<u32>,
    batches: &mut Vec<Batch>,
) {
    batches.clear();
    order.clear();
    let colored = matches!(
        config.order,
        SolveOrder::Colored | SolveOrder::ColoredInRounds
    ) && coloring.colors.len() == contacts.len();
    if !colored {
        order.extend(0..contacts.len() as u32);
        batches.push(Batch {
            range: 0..contacts.len(),
            parallel: false,
            color: false,
            lanes: 0..0,
            scalar: 0..0,
        });
        return;
    }
    order.extend_from_slice(&coloring.order);
    batches.extend(
        (0..=OVERFLOW_COLOR)
            .map(|c| {
                let range = coloring.offsets[c as usize] as usize
                    ..coloring.offsets[c as usize + 1] as usize;
                let color = c != OVERFLOW_COLOR;
                let parallel = color && range.len() >= config.parallel_threshold as usize;
                Batch {
                    range,
                    parallel,
                    color,
                    lanes: 0..0,
                    scalar: 0..0,
                }
            })
            .filter(|b| !b.range.is_empty()),
    );
}

/// How many constraints ahead [`check_batches`] asks for a contact's body indices.
const CHECK_AHEAD: usize = 24;
/// Constraints from which [`check_batches`] checks the colors on the pool.
const PARALLEL_CHECK_MIN: usize = 16_384;

/// Makes sure every color's batch shares no dynamic body between its constraints, which the
/// in-place parallel sweep and the lanes rely on; a batch that does (a coloring that is not
/// one) is visited sequentially by the scalar kernel, which gives the reference result. With
/// a lane kernel, gives each checked batch its lane blocks' range (and a sequential one with
/// at most [`SCALAR_TAIL`] constraints past its last full block, those as scalar constraints
/// after the blocks); every other batch gets its range of scalar constraints. Returns the
/// number of lane blocks and of scalar constraints.
fn check_batches(
    bodies: &[Body],
    contacts: &[Contact],
    order: &[u32],
    batches: &mut [Batch],
    stamps: &mut Vec<u32>,
    kernel: SolveKernel,
) -> (usize, usize) {
    // Batch `k`'s body pairs, in visiting order.
    let ends = |batch: &Batch| {
        let members = &order[batch.range.clone()];
        members.iter().enumerate().map(move |(n, &i)| {
            // The contacts are read in color order, all over the array (67 MB on the
            // pyramid of 50, where this loop took 12 ms on one thread): ask for the body
            // indices of the one CHECK_AHEAD on.
            if let Some(c) = members
                .get(n + CHECK_AHEAD)
                .and_then(|&j| contacts.get(j as usize))
            {
                lanes::prefetch(&c.body_a);
            }
            let c = &contacts[i as usize];
            [c.body_a, c.body_b].map(|body| {
                let dynamic = bodies.get(body as usize).is_some_and(Body::is_dynamic);
                (body, dynamic)
            })
        })
    };
    // Each color is checked against its own stamp (its index), so the colors may be checked
    // side by side, each task with its own stamp array (a stamp written by another color
    // never equals this one's). Each task fills an array as long as the body list, so a
    // scene of far more bodies than constraints (a sparse field of boxes) keeps to one.
    let side_by_side = order.len() >= PARALLEL_CHECK_MIN
        && bodies.len() <= 2 * order.len()
        && rayon::current_num_threads() > 1;
    let checked: Vec<bool> = if side_by_side {
        batches
            .par_iter()
            .enumerate()
            .with_max_len(1)
            .map_init(
                || vec![u32::MAX; bodies.len()],
                |stamps, (k, batch)| batch.color && check_disjoint(ends(batch), stamps, k as u32),
            )
            .collect()
    } else {
        stamps.clear();
        stamps.resize(bodies.len(), u32::MAX);
        batches
            .iter()
            .enumerate()
            .map(|(k, batch)| batch.color && check_disjoint(ends(batch), stamps, k as u32))
            .collect()
    };
    let (mut blocks, mut scalar) = (0, 0);
    for (batch, &disjoint) in batches.iter_mut().zip(&checked) {
        batch.parallel &= disjoint;
        let n = batch.range.len();
        if disjoint && kernel != SolveKernel::Scalar {
            // A sequential color's last few constraints go to the scalar kernel (the same
            // bits: tests/tests/solver_kernels.rs) rather than a block of mostly padding
            // lanes, which costs as much as a full one.
            let tail = match n % LANES {
                t if !batch.parallel && n > LANES && t <= SCALAR_TAIL => t,
                _ => 0,
            };
            let count = (n - tail).div_ceil(LANES);
            batch.lanes = blocks..blocks + count;
            batch.scalar = scalar..scalar + tail;
            blocks += count;
            scalar += tail;
        } else {
            batch.lanes = 0..0;
            batch.scalar = scalar..scalar + n;
            scalar += n;
        }
    }
    (blocks, scalar)
}

/// Runs the solve stage for one step of length `dt`.
///
/// Velocities and deltas in `states` advance; poses in `bodies` stay at the start of the step
/// until [`crate::finalize_bodies`]. Each contact's `impulses` are read as the warm start and
/// overwritten with this step's impulses, and `total_normal_impulse` is filled. `coloring` is
/// used when `config.order` is `Colored` and it colors exactly `contacts`; otherwise the
/// reference sequential order runs.
pub fn solve(
    bodies: &[Body],
    states: &mut [BodyState],
    contacts: &mut [Contact],
    coloring: &Coloring,
    config: &SolverConfig,
    dt: Real,
    gravity: &Vec3,
) -> SolveStats {
    solve_with_effects(
        bodies,
        states,
        contacts,
        coloring,
        config,
        dt,
        gravity,
        &Effects::ALL,
    )
}

/// [`solve`] with the effects that are off left out: no gravity term, no friction rows, no
/// angular velocity update, no restitution pass. With an effect on, the general code runs and
/// decides per constraint (a contact of zero friction skips its friction rows, one of zero
/// restitution its restitution rows), so for a scene that does not use an effect both give
/// the same bits; an effect turned off that the scene does use is left out all the same.
#[allow(clippy::too_many_arguments)]
pub fn solve_with_effects(
    bodies: &[Body],
    states: &mut [BodyState],
    contacts: &mut [Contact],
    coloring: &Coloring,
    config: &SolverConfig,
    dt: Real,
    gravity: &Vec3,
    effects: &Effects,
) -> SolveStats {
    solve_with_buffers(
        bodies,
        states,
        contacts,
        coloring,
        config,
        dt,
        gravity,
        effects,
        &mut SolveBuffers::default(),
    )
}

/// [`solve_with_effects`] with its working memory in `buffers`, which a caller that steps
/// again keeps: the same bits, without allocating the constraints every step.
#[allow(clippy::too_many_arguments)]
pub fn solve_with_buffers(
    bodies: &[Body],
    states: &mut [BodyState],
    contacts: &mut [Contact],
    coloring: &Coloring,
    config: &SolverConfig,
    dt: Real,
    gravity: &Vec3,
    effects: &Effects,
    buffers: &mut SolveBuffers,
) -> SolveStats {
    let kernel = &config.kernel;
    let SolveBuffers {
        constraints,
        blocks,
        inverse_inertia,
        order,
        batches,
        stamps,
        source,
    } = buffers;
    let substeps = config.substeps.max(1);
    let h = dt / substeps as Real;
    let inv_h = 1.0 / h;
    let (contact_softness, static_softness) = config.softness(h);
    let prepare_ctx = PrepareContext {
        kind: config.kind,
        h,
        contact_softness,
        static_softness,
        slop: config.slop,
        warm_start_scale: if config.warm_start { 1.0 } else { 0.0 },
    };

    begin_step(states);
    // Rotation off: no body turns, as on the GPU (whose body passes zero the inverse inertia
    // and the spin): contacts then push without torque and the integrator adds no spin. For
    // a scene that needs no rotation (every moving body dynamic with all rotations locked)
    // both are zero already, so the result bits do not change.
    inverse_inertia.clear();
    if effects.rotation {
        inverse_inertia.extend(bodies.iter().map(Body::inverse_inertia_world));
    } else {
        for s in states.iter_mut() {
            s.angular_velocity = Vec3::zeros();
        }
        inverse_inertia.resize(bodies.len(), Mat3::zeros());
    }
    plan(contacts, coloring, config, order, batches);
    let (block_count, scalar_count) =
        check_batches(bodies, contacts, order, batches, stamps, *kernel);
    let inverse_inertia: &[Mat3] = inverse_inertia;
    let prepare = |&i: &u32| {
        let mut c = prepare_contact(
            bodies,
            inverse_inertia,
            states,
            contacts,
            i as usize,
            &prepare_ctx,
        );
        if !effects.friction {
            // A zero coefficient is what makes the passes skip the tangent rows; the warm
            // start must not re-apply friction impulses carried from before the effect went
            // off.
            c.friction = 0.0;
            for p in &mut c.points {
                p.tangent_impulse = [0.0; 2];
            }
        }
        c
    };
    let isa = match kernel {
        SolveKernel::Lanes => Isa::detect(),
        SolveKernel::PortableLanes | SolveKernel::Scalar => Isa::Portable,
    };
    // Each lane block is prepared in place, its points' rows eight lanes at a time; the
    // scalar constraints one by one. A lane batch's constraints never go through memory in
    // between.
    let inputs = PrepareSource {
        bodies,
        inverse_inertia,
        states,
        contacts,
        ctx: &prepare_ctx,
        friction: effects.friction,
    };
    // On a pool of one thread a parallel loop only hands the work to that thread (and from
    // outside the pool, sleeps until it is done).
    let wide = order.len() >= PARALLEL_PREPARE_MIN && rayon::current_num_threads() > 1;
    constraints.clear();
    constraints.reserve(scalar_count);
    // Blocks kept from the last step are overwritten by `LaneBlock::prepare`.
    blocks.resize(block_count, LaneBlock::default());
    for batch in batches.iter() {
        let indices = &order[batch.range.clone()];
        // The batch's scalar constraints: all of it, or a lane batch's tail.
        let (indices, tail) = indices.split_at(indices.len() - batch.scalar.len());
        if batch.lanes.is_empty() {
            if wide {
                constraints.par_extend(tail.par_iter().map(prepare));
            } else {
                constraints.extend(tail.iter().map(prepare));
            }
            continue;
        }
        constraints.extend(tail.iter().map(prepare));
        let out = &mut blocks[batch.lanes.clone()];
        if wide {
            // Runs of blocks, each prefetching within itself: two per thread, from
            // PREPARE_MIN_RUN to PREPARE_MAX_RUN blocks.
            let run = out
                .len()
                .div_ceil(2 * rayon::current_num_threads())
                .clamp(PREPARE_MIN_RUN, PREPARE_MAX_RUN);
            out.par_chunks_mut(run)
                .zip(indices.par_chunks(run * LANES))
                .for_each(|(out, indices)| prepare_blocks(out, indices, &inputs, isa));
        } else {
            prepare_blocks(out, indices, &inputs, isa);
        }
    }
    let gravity = effects.gravity.then_some(gravity);

    let biased = Velocity(config.pass_context(inv_h, true));
    let relaxed = Velocity(config.pass_context(inv_h, false));
    let mut set = SweepSet {
        constraints,
        blocks,
        batches,
        inverse_inertia,
        isa,
    };
    for _ in 0..substeps {
        integrate_velocities_with(bodies, states, gravity, effects.rotation, h);
        sweep(&mut set, states, &WarmStart);
        for _ in 0..config.iterations {
            sweep(&mut set, states, &biased);
        }
        integrate_positions(bodies, states, h);
        for _ in 0..config.relax_iterations {
            sweep(&mut set, states, &relaxed);
        }
    }
    // The scan reads a line of every block (4 MB of scattered lines on the pyramid of 50):
    // only when the effect is on.
    let restitution = effects.restitution
        && (set.constraints.iter().any(|c| c.restitution > 0.0)
            || set.blocks.iter().any(LaneBlock::has_restitution));
    if restitution {
        sweep(&mut set, states, &Restitution(config.restitution_threshold));
    }
    if order.len() >= PARALLEL_PREPARE_MIN && rayon::current_num_threads() > 1 {
        // Each contact's impulses come from exactly one constraint or lane, found through
        // `source`, so every contact is written by one task, with the same operations as
        // the serial stores below. `source` is filled from the visiting order, which the
        // prepare filled the constraints and the lanes from (a batch's lanes take its first
        // members, eight to a block; its scalar constraints the rest), rather than from each
        // block's contact field (a line of every block, 2.6 to 2.9 ms on the pyramid of 50):
        // the scalar constraints first, then the lanes, as the serial stores write them.
        source.clear();
        source.resize(contacts.len(), NO_SOURCE);
        for batch in batches.iter() {
            let members = &order[batch.range.clone()];
            let tail = &members[members.len() - batch.scalar.len()..];
            for (k, &i) in batch.scalar.clone().zip(tail) {
                source[i as usize] = SCALAR_SOURCE | k as u32;
            }
        }
        for batch in batches.iter() {
            let members = &order[batch.range.clone()];
            let lanes = &members[..members.len() - batch.scalar.len()];
            let first = batch.lanes.start * LANES;
            for (j, &i) in lanes.iter().enumerate() {
                source[i as usize] = (first + j) as u32;
            }
        }
        let (constraints, blocks): (&[ContactConstraint], &[LaneBlock]) = (constraints, blocks);
        contacts
            .par_iter_mut()
            .zip(source.par_iter())
            .with_min_len(STORE_PER_TASK)
            .for_each(|(contact, &from)| match from {
                NO_SOURCE => {}
                f if f & SCALAR_SOURCE != 0 => {
                    constraints[(f & !SCALAR_SOURCE) as usize].store_impulses(contact);
                }
                f => blocks[f as usize / LANES].store_lane(f as usize % LANES, contact),
            });
    } else {
        for c in constraints.iter() {
            c.store_impulses(&mut contacts[c.contact as usize]);
        }
        // The lanes' contacts lie all over the array, as in the prepare: each block first
        // asks for those of the block two ahead.
        for (k, b) in blocks.iter().enumerate() {
            if let Some(ahead) = blocks.get(k + 2) {
                for l in 0..ahead.len() {
                    if let Some(c) = contacts.get(ahead.contact_of(l)) {
                        lanes::prefetch(c);
                    }
                }
            }
            b.store(contacts);
        }
    }
    SolveStats {
        constraints: order.len(),
        points: contacts.iter().map(|c| c.manifold.len as usize).sum(),
        parallel_batches: batches.iter().filter(|b| b.parallel).count(),
    }
}
