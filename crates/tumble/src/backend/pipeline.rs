//! The step on the host, written once for `Backend::Cpu` and `Backend::Hybrid`: the stages of
//! [`Stage::ALL`] in order, with the collision stages (update_aabbs, broad and narrow phase)
//! supplied by a [`Collision`] (the CPU's, or the GPU's for Hybrid), and color, solve,
//! finish and sleep run on the CPU.
//!
//! While some bodies sleep, the step runs on the [`Gathered`] copy of the bodies (the awake
//! ones, then the sleepers as fixed obstacles; see [`tumble_solver::SleepState`]): the
//! collision stages report manifolds in gathered indices, the solver moves only the awake
//! bodies, and the sleeping islands' kept manifolds join the step's for reports and warm
//! starting.

use rayon::prelude::*;
use tumble_geometry::Real;
use tumble_solver::{
    Body, BodyState, Contact, Gathered, PairKey, SolveBuffers, Stage, bounds, stages,
};

use super::{Host, StepArgs};
use crate::stats::StageClock;
use crate::{BodyHandle, Error, StepStats};

/// Bodies below which the solved states are checked on the calling thread (a check costs
/// tens of nanoseconds, a rayon task a few microseconds).
const PARALLEL_MIN_BODIES: usize = 2048;

/// Bodies per rayon task when the solved states are checked in parallel.
const BODIES_PER_TASK: usize = 512;

/// Manifolds below which the report's handles and deepest overlap are computed on the
/// calling thread.
const PARALLEL_MIN_CONTACTS: usize = 8192;

// The CPU backend runs a step on the calling thread when the last one was below
// `runs_on_one_thread`'s sizes; these loops must not go wide below them either.
const _: () = assert!(
    !tumble_solver::stages::runs_on_one_thread(PARALLEL_MIN_BODIES, 0)
        && !tumble_solver::stages::runs_on_one_thread(0, PARALLEL_MIN_CONTACTS)
);

/// Manifolds per rayon task when they are computed in parallel.
const CONTACTS_PER_TASK: usize = 2048;

/// The bodies the collision stages run on.
// The dense arrays and handles are read by the GPU's collision (`Backend::Hybrid`) only.
#[cfg_attr(not(feature = "gpu"), allow(dead_code))]
pub(crate) struct StepBodies<'a> {
    /// The step's bodies: the host's, or their gathered copy while some sleep.
    pub bodies: &'a [Body],
    /// The step's states, parallel to `bodies`.
    pub states: &'a [BodyState],
    /// The stable id (handle bits) of each of the step's bodies.
    pub ids: &'a [u64],
    /// The gathered copy, when the step runs on one.
    pub gathered: Option<&'a Gathered>,
    /// The host's bodies, dense order.
    pub dense_bodies: &'a [Body],
    /// The host's states, dense order.
    pub dense_states: &'a [BodyState],
    /// The handle of each dense body.
    pub handles: &'a [BodyHandle],
    /// The base speculative margin, m.
    pub margin: Real,
    /// The step, s.
    pub dt: Real,
    /// `WorldConfig::recycle_distance`, m (0: every manifold afresh).
    pub recycle_distance: Real,
}

/// What the collision stages found.
#[derive(Debug, Default)]
pub(crate) struct Collided {
    /// The manifolds, indices into [`StepBodies::bodies`].
    pub contacts: Vec<Contact>,
    /// The stable pair key of each manifold.
    pub keys: Vec<PairKey>,
    /// Candidate pairs examined.
    pub pairs: usize,
}

/// Stages 1-3 and the persistence half of stage 7: where the manifolds come from and where
/// their impulses go for the next step's warm start.
pub(crate) trait Collision {
    /// Runs the collision stages on `step`, ending each stage on `clock`.
    fn collide(&mut self, step: &StepBodies<'_>, clock: &mut StageClock)
    -> Result<Collided, Error>;

    /// Keeps the step's impulses for the next step: `contacts` (dense indices) and their
    /// `keys`, of which the first `solved` were solved this step (the rest are the sleeping
    /// islands' kept manifolds); `bodies` hold the poses the manifolds came from.
    fn keep_impulses(
        &mut self,
        keys: &[PairKey],
        contacts: &[Contact],
        solved: usize,
        bodies: &[Body],
    ) -> Result<(), Error>;

    /// The solve stage's working memory, kept between steps (the constraints alone are
    /// megabytes on a large pile); `None` solves with fresh buffers each step. Either gives
    /// the same bits.
    fn solve_buffers(&mut self) -> Option<&mut SolveBuffers> {
        None
    }

    /// Takes back the arrays of an earlier step's manifolds and pair keys, done with, for the
    /// next narrow phase to write over; dropped by default.
    fn give_back(&mut self, contacts: Vec<Contact>, keys: Vec<PairKey>) {
        drop((contacts, keys));
    }
}

/// One step of `host` on the CPU stages, collision by `collision`.
pub(crate) fn step(
    host: &mut Host,
    args: StepArgs<'_>,
    collision: &mut dyn Collision,
) -> Result<(), Error> {
    let StepArgs {
        handles,
        config,
        effects,
    } = args;
    let dense = |id: u64| handles.dense_of_bits(id);
    let all_handles = handles.handles();
    let dt = config.dt;
    let mut clock = StageClock::start();
    let mut gathered = None;
    if effects.sleep && host.sleep.asleep_count() > 0 {
        // Sleeping contacts whose islands woke rejoin the narrow phase through the cache.
        host.sleep.drop_woken_contacts(dense);
        let g = host.sleep.gather(&host.bodies, &host.states);
        if !g.any_moving() {
            // Nothing can move or touch: the step is empty, the sleepers' manifolds stay.
            let (contacts, _): (Vec<Contact>, Vec<PairKey>) =
                host.sleep.sleeping_contacts(dense).unzip();
            let replaced = set_contacts(host, contacts, all_handles);
            collision.give_back(replaced, Vec::new());
            host.contact_colors.clear();
            host.stats = StepStats {
                bodies: host.bodies.len(),
                ..Default::default()
            };
            return Ok(());
        }
        gathered = Some(g);
    }
    let ids: Vec<u64> = match &gathered {
        Some(g) => g.order.iter().map(|&d| all_handles[d].to_bits()).collect(),
        None => all_handles.iter().map(BodyHandle::to_bits).collect(),
    };
    let (bodies, states) = match &gathered {
        Some(g) => (&g.bodies[..], &g.states[..]),
        None => (&host.bodies[..], &host.states[..]),
    };
    let collided = collision.collide(
        &StepBodies {
            bodies,
            states,
            ids: &ids,
            gathered: gathered.as_ref(),
            dense_bodies: &host.bodies,
            dense_states: &host.states,
            handles: all_handles,
            margin: config.margin,
            dt,
            recycle_distance: config.recycle_distance,
        },
        &mut clock,
    )?;
    let pairs = collided.pairs;
    let (mut contacts, mut keys) = (collided.contacts, collided.keys);
    // The sleepers this step reaches wake for the next one.
    let mut to_wake = Vec::new();
    if let Some(g) = &gathered {
        if effects.kinematic {
            to_wake.extend(g.kinematic_reach(config.margin, dt));
        }
        to_wake.extend(g.touched_sleepers(&contacts));
    }
    clock.lap(Stage::Sleep);

    // The solve writes the host's states in place when no body sleeps: kept, so that a
    // refused step can put them back (the gathered copy leaves the host's untouched).
    let before = gathered.is_none().then(|| host.states.clone());
    let (bodies, states) = match gathered.as_mut() {
        Some(g) => (&g.bodies[..], &mut g.states[..]),
        None => (&host.bodies[..], &mut host.states[..]),
    };
    let coloring = stages::color(&contacts, bodies, config.solver.order, &config.gravity);
    clock.lap(Stage::Color);
    let mut fresh = SolveBuffers::default();
    let solve_buffers = collision.solve_buffers().unwrap_or(&mut fresh);
    let solved = tumble_solver::solve_with_buffers(
        bodies,
        states,
        &mut contacts,
        &coloring,
        &config.solver,
        dt,
        &config.gravity,
        effects,
        solve_buffers,
    );
    clock.lap(Stage::Solve);
    // Nothing is committed yet (poses, the contact cache, sleep): a state out of bounds
    // refuses the step and leaves the world as it was.
    let refused = match &gathered {
        Some(g) => check_solved(&g.bodies, &g.states, |i| all_handles[g.order[i]]),
        None => check_solved(&host.bodies, &host.states, |i| all_handles[i]),
    };
    if let Some(e) = refused {
        if let Some(states) = before {
            host.states = states;
        }
        collision.give_back(contacts, keys);
        return Err(e);
    }

    // Back to dense indices, then the sleeping islands' manifolds, which stay in the cache
    // for when they wake.
    let solved_contacts = contacts.len();
    if let Some(g) = &gathered {
        g.to_dense(&mut contacts);
        for (c, key) in host.sleep.sleeping_contacts(dense) {
            contacts.push(c);
            keys.push(key);
        }
    }
    // The impulses are kept in body A's frame at the poses the manifolds came from, so
    // before the poses move.
    collision.keep_impulses(&keys, &contacts, solved_contacts, &host.bodies)?;
    match gathered.as_mut() {
        Some(g) => g.finish_into(&mut host.bodies, &mut host.states),
        None => tumble_solver::finalize_bodies(&mut host.bodies, &mut host.states),
    }
    clock.lap(Stage::Finish);

    let max_penetration = max_penetration(&contacts);
    let replaced = set_contacts(host, contacts, all_handles);
    // The solved manifolds come first, in the coloring's order; the kept ones have none.
    host.contact_colors.clone_from(&coloring.colors);
    if !host.contact_colors.is_empty() {
        let n = host.contacts.len();
        host.contact_colors.resize(n, tumble_solver::NO_COLOR);
    }
    for d in to_wake {
        host.sleep.wake(d);
    }
    if effects.sleep {
        host.sleep.update(
            &host.bodies,
            &mut host.states,
            &host.contacts,
            &keys,
            dt,
            effects.kinematic,
        );
    }
    clock.lap(Stage::Sleep);

    host.stats = StepStats {
        bodies: host.bodies.len(),
        pairs,
        manifolds: host.contacts.len(),
        recycled_manifolds: host.contacts.iter().filter(|c| c.recycled).count(),
        contact_points: solved.points,
        colors: coloring.used_colors(),
        overflow: if coloring.colors.is_empty() {
            0
        } else {
            coloring.overflow_count()
        },
        parallel_colors: solved.parallel_batches,
        max_penetration,
        timings: clock.timings(),
    };
    // Last step's manifolds and this step's keys are done with: their arrays go back to the
    // collision stages to be written over (megabytes on a large pile, allocated once).
    collision.give_back(replaced, keys);
    Ok(())
}

/// The error for the first body whose solved state leaves its bounds
/// ([`tumble_solver::bounds::check_solved`]); `handle` names the body at a step index.
fn check_solved(
    bodies: &[Body],
    states: &[BodyState],
    handle: impl Fn(usize) -> BodyHandle,
) -> Option<Error> {
    let check =
        |(i, (b, s)): (usize, (&Body, &BodyState))| bounds::check_solved(b, s).map(|v| (i, v));
    // The first violation by index on either path, so the error names the same body.
    let first = if bodies.len() >= PARALLEL_MIN_BODIES && rayon::current_num_threads() > 1 {
        bodies
            .par_iter()
            .zip(states)
            .enumerate()
            .with_min_len(BODIES_PER_TASK)
            .find_map_first(check)
    } else {
        bodies.iter().zip(states).enumerate().find_map(check)
    };
    first.map(|(i, v)| Error::InvalidStep {
        body: handle(i),
        quantity: v.quantity,
        value: v.value,
        expected: v.expected,
    })
}

/// Last step's manifolds become `contacts` (dense indices), with their bodies' handles;
/// returns the manifolds they replace.
fn set_contacts(host: &mut Host, contacts: Vec<Contact>, handles: &[BodyHandle]) -> Vec<Contact> {
    let pair = |c: &Contact| (handles[c.body_a as usize], handles[c.body_b as usize]);
    if contacts.len() >= PARALLEL_MIN_CONTACTS && rayon::current_num_threads() > 1 {
        contacts
            .par_iter()
            .with_min_len(CONTACTS_PER_TASK)
            .map(pair)
            .collect_into_vec(&mut host.contact_handles);
    } else {
        host.contact_handles.clear();
        host.contact_handles.extend(contacts.iter().map(pair));
    }
    std::mem::replace(&mut host.contacts, contacts)
}

/// The broad phase's candidate pairs `pairs` (indices into [`StepBodies::bodies`]) by
/// handle, the body of the lower dense index first, sorted by dense indices, into `out`
/// (its old contents replaced, its allocation kept). On the pool from
/// [`PARALLEL_MIN_CONTACTS`] pairs: the same list (the sort's keys are distinct pairs).
pub(crate) fn pair_handles(
    step: &StepBodies<'_>,
    pairs: &[(u32, u32)],
    out: &mut Vec<(BodyHandle, BodyHandle)>,
) {
    let dense = |&(a, b): &(u32, u32)| {
        let (a, b) = match step.gathered {
            Some(g) => (g.order[a as usize], g.order[b as usize]),
            None => (a as usize, b as usize),
        };
        (a.min(b), a.max(b))
    };
    let handles = |&(a, b): &(usize, usize)| (step.handles[a], step.handles[b]);
    if pairs.len() >= PARALLEL_MIN_CONTACTS && rayon::current_num_threads() > 1 {
        let mut dense_pairs = Vec::with_capacity(pairs.len());
        pairs
            .par_iter()
            .with_min_len(CONTACTS_PER_TASK)
            .map(dense)
            .collect_into_vec(&mut dense_pairs);
        dense_pairs.par_sort_unstable();
        dense_pairs
            .par_iter()
            .with_min_len(CONTACTS_PER_TASK)
            .map(handles)
            .collect_into_vec(out);
    } else {
        let mut dense_pairs: Vec<(usize, usize)> = pairs.iter().map(dense).collect();
        dense_pairs.sort_unstable();
        out.clear();
        out.extend(dense_pairs.iter().map(handles));
    }
}

/// The deepest overlap among `contacts`, m (0 when none overlaps).
pub(crate) fn max_penetration(contacts: &[Contact]) -> Real {
    let depth = |c: &Contact| c.manifold.max_depth();
    if contacts.len() >= PARALLEL_MIN_CONTACTS && rayon::current_num_threads() > 1 {
        // The largest positive depth is one value whatever order the maxima are taken in, and
        // it is what the fold below returns when some depth is positive. Without one (no
        // overlap, or the sign of a zero at stake) the fold decides.
        let deepest = contacts
            .par_iter()
            .with_min_len(CONTACTS_PER_TASK)
            .map(depth)
            .filter(|&d| d > 0.0)
            .reduce_with(Real::max);
        if let Some(d) = deepest {
            return d;
        }
    }
    contacts.iter().map(depth).fold(0.0, Real::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_geometry::{ContactPoint, Manifold, Point3, Vec3};

    /// A manifold of one point at `depth`.
    fn contact(depth: Real) -> Contact {
        let mut m = Manifold {
            normal: Vec3::y(),
            ..Default::default()
        };
        m.push(ContactPoint {
            position: Point3::origin(),
            depth,
            id: 0,
        });
        Contact::new(0, 1, m)
    }

    #[test]
    fn the_deepest_overlap_is_the_serial_folds_on_any_pool() {
        // 20,000 manifolds (past PARALLEL_MIN_CONTACTS), depths spread over -5..5 mm with one
        // deepest at 7.25 mm placed in the middle: the pool's reduction must find exactly it.
        let mut contacts: Vec<Contact> = (0..20_000)
            .map(|i| contact(((i * 7919) % 10_000) as Real * 1e-6 - 0.005))
            .collect();
        contacts[12_345] = contact(0.00725);
        // None overlapping: 0 (the fold's start), not the least negative depth.
        let apart: Vec<Contact> = (0..20_000).map(|i| contact(-0.001 - i as Real)).collect();
        for threads in [1, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let deepest = pool.install(|| max_penetration(&contacts));
            assert_eq!(deepest.to_bits(), 0.00725f32.to_bits(), "{threads} threads");
            assert_eq!(pool.install(|| max_penetration(&apart)).to_bits(), 0);
        }
    }
}
