//! `Backend::Cpu`: every stage on the CPU, the reference.

use tumble_broad::KeptPairs;
use tumble_solver::stages::{self, NarrowBuffers};
use tumble_solver::{Body, Contact, ContactCache, PairKey, SolveBuffers, Stage};

use super::pipeline::{self, Collided, Collision, StepBodies};
use super::{Host, StepArgs, StepBackend};
use crate::snapshot::{BackendSnapshot, wrong_backend};
use crate::stats::StageClock;
use crate::{Backend, BodyHandle, Error};

/// The CPU collision stages: the grid broad phase, the box-box test, the contact cache.
#[derive(Debug, Default)]
pub(crate) struct CpuCollision {
    /// The broad phase's pair list and buffers, kept between steps.
    grid: KeptPairs,
    /// Last step's impulses by body pair, for warm starting.
    cache: ContactCache,
    /// The solve stage's buffers, kept between steps.
    solve: SolveBuffers,
    /// The narrow phase's buffers, kept between steps.
    narrow: NarrowBuffers,
    /// Last step's candidate pairs from the broad phase, by handle.
    pairs: Vec<(BodyHandle, BodyHandle)>,
    /// The array of the list before last step's, written over by the next step.
    spare_pairs: Vec<(BodyHandle, BodyHandle)>,
    /// The broad phase's pairs by step index, an array kept between steps.
    broad_pairs: Vec<(u32, u32)>,
}

impl Collision for CpuCollision {
    fn collide(
        &mut self,
        step: &StepBodies<'_>,
        clock: &mut StageClock,
    ) -> Result<Collided, Error> {
        let (margin, dt) = (step.margin, step.dt);
        let aabbs = stages::update_aabbs(step.bodies, step.states, margin, dt);
        clock.lap(Stage::UpdateAabbs);
        let mut pairs = std::mem::take(&mut self.broad_pairs);
        stages::broad_phase_into(&mut self.grid, &aabbs, step.bodies, &mut pairs);
        pipeline::pair_handles(step, &pairs, &mut self.pairs);
        clock.lap(Stage::BroadPhase);
        let found = stages::narrow_phase_with(
            step.bodies,
            step.states,
            &pairs,
            step.ids,
            &self.cache,
            margin,
            dt,
            step.recycle_distance,
            &mut self.narrow,
        );
        clock.lap(Stage::NarrowPhase);
        let count = pairs.len();
        self.broad_pairs = pairs;
        Ok(Collided {
            contacts: found.contacts,
            keys: found.keys,
            pairs: count,
        })
    }

    fn keep_impulses(
        &mut self,
        keys: &[PairKey],
        contacts: &[Contact],
        _solved: usize,
        bodies: &[Body],
    ) -> Result<(), Error> {
        self.cache.store(keys, contacts, bodies);
        Ok(())
    }

    fn solve_buffers(&mut self) -> Option<&mut SolveBuffers> {
        Some(&mut self.solve)
    }

    fn give_back(&mut self, contacts: Vec<Contact>, keys: Vec<PairKey>) {
        self.narrow.give_back(contacts, keys);
    }
}

/// `Backend::Cpu`: [`pipeline::step`] with [`CpuCollision`]; every result lives on the host.
#[derive(Debug, Default)]
pub(crate) struct CpuBackend {
    collision: CpuCollision,
    /// The last step's candidate pair count; `None` before the first step.
    last_pairs: Option<usize>,
}

impl StepBackend for CpuBackend {
    fn step(&mut self, host: &mut Host, args: StepArgs<'_>) -> Result<(), Error> {
        // Last step's pair list, kept for a refused step; this step writes into the array of
        // the list before it (two arrays in turn, so a large list is not allocated anew).
        // Cleared here: a step in which nothing can move never reaches the broad phase, and
        // its list must then be empty, not the one before last.
        let mut spare = std::mem::take(&mut self.collision.spare_pairs);
        spare.clear();
        let before = std::mem::replace(&mut self.collision.pairs, spare);
        // The whole step on a worker of the pool: every stage's parallel loop then starts
        // from inside the pool, where the calling worker takes part, instead of handing each
        // loop to the pool from outside and sleeping until it is done (a wake-up and a sleep
        // of this thread per loop, dozens a step). A step that no stage would spread (on a
        // pool of one thread, or with as few bodies and pairs as `runs_on_one_thread` allows,
        // judged by the last step's pairs) runs on the calling thread instead: there the
        // hand-off would be all the pool adds, a wake-up and a sleep per step, much of a small
        // scene's step (docs/benchmarks.md, "CPU step: small scenes on the calling thread").
        // The result does not depend on where the step runs.
        let collision = &mut self.collision;
        let small = self
            .last_pairs
            .is_some_and(|pairs| stages::runs_on_one_thread(host.bodies.len(), pairs));
        let stepped = if small || rayon::current_num_threads() == 1 {
            pipeline::step(host, args, collision)
        } else {
            rayon::scope(|_| pipeline::step(host, args, collision))
        };
        if stepped.is_err() {
            self.collision.spare_pairs = std::mem::replace(&mut self.collision.pairs, before);
        } else {
            self.collision.spare_pairs = before;
            self.last_pairs = Some(self.collision.pairs.len());
        }
        stepped
    }

    fn broad_phase_pairs(&self) -> &[(BodyHandle, BodyHandle)] {
        &self.collision.pairs
    }

    fn forget_body(&mut self, id: u64) {
        self.collision.cache.forget_body(id);
    }

    fn kind(&self) -> Backend {
        Backend::Cpu
    }

    fn save(&self) -> Result<BackendSnapshot, Error> {
        Ok(BackendSnapshot::Cpu {
            cache: self.collision.cache.entries(),
        })
    }

    // Without the `gpu` feature the Cpu state is the only kind.
    #[cfg_attr(not(feature = "gpu"), allow(irrefutable_let_patterns))]
    fn load(&mut self, saved: &BackendSnapshot, _host: &Host) -> Result<(), Error> {
        let BackendSnapshot::Cpu { cache } = saved else {
            return Err(wrong_backend(saved, self.kind()));
        };
        self.collision.cache = ContactCache::from_entries(cache.iter().copied());
        Ok(())
    }
}
