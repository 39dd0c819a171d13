//! The world: bodies, configuration, and the step as a sequence of stages.

use std::time::Instant;

use tumble_broad::SweepAndPrune;
use tumble_geometry::Real;
use tumble_solver::{Body, BodyState, Contact, ContactCache};

use crate::{
    BodyHandle, ContactPointReport, ContactReport, Error, StageTimings, StepStats, WorldConfig,
    handle::HandleMap, stages,
};

/// A simulated world of boxes.
///
/// Bodies live in dense arrays (cold [`Body`] data and hot [`BodyState`]) addressed through
/// [`BodyHandle`]s; the step runs the stages of [`crate::stages`] in order.
#[derive(Debug)]
pub struct World {
    pub(crate) config: WorldConfig,
    pub(crate) handles: HandleMap,
    pub(crate) bodies: Vec<Body>,
    pub(crate) states: Vec<BodyState>,
    /// Last step's manifolds (dense body indices at the time of the step).
    pub(crate) contacts: Vec<Contact>,
    /// The body handles of each of last step's manifolds.
    pub(crate) contact_handles: Vec<(BodyHandle, BodyHandle)>,
    pub(crate) cache: ContactCache,
    /// Rest timers, sleeping islands and their contacts.
    pub(crate) sleep: crate::sleep::SleepState,
    sap: SweepAndPrune,
    pub(crate) stats: StepStats,
    steps: u64,
    /// The GPU side of `Backend::Gpu` and `Backend::Hybrid`.
    pub(crate) gpu: Option<crate::gpu_backend::GpuBackend>,
}

impl World {
    /// An empty world. Errs on a bad config (naming the field) or an unavailable backend.
    pub fn new(config: WorldConfig) -> Result<Self, Error> {
        config.validate()?;
        let gpu = crate::gpu_backend::GpuBackend::new(&config)?;
        Ok(Self {
            config,
            handles: HandleMap::default(),
            bodies: Vec::new(),
            states: Vec::new(),
            contacts: Vec::new(),
            contact_handles: Vec::new(),
            cache: ContactCache::new(),
            sleep: Default::default(),
            sap: SweepAndPrune::new(),
            stats: StepStats::default(),
            steps: 0,
            gpu,
        })
    }

    /// The configuration the world runs with.
    pub fn config(&self) -> &WorldConfig {
        &self.config
    }

    /// Steps taken so far.
    pub fn step_count(&self) -> u64 {
        self.steps
    }

    /// Simulated time so far, s.
    pub fn time(&self) -> f64 {
        self.steps as f64 * f64::from(self.config.dt)
    }

    /// Advances the world by `config.dt`.
    pub fn step(&mut self) -> Result<(), Error> {
        if let Some(stats) = self.step_on_gpu()? {
            self.stats = stats;
            self.steps += 1;
            return Ok(());
        }
        let effects = self.effects();
        if let Some(stats) = self.step_with_sleepers(&effects) {
            self.stats = stats;
            self.steps += 1;
            return Ok(());
        }
        let dt = self.config.dt;
        let mut timings = StageTimings::default();
        let mut clock = Instant::now();
        let mut lap = |slot: &mut std::time::Duration| {
            let now = Instant::now();
            *slot = now - clock;
            clock = now;
        };

        let aabbs = stages::update_aabbs(&self.bodies, &self.states, self.config.margin, dt);
        lap(&mut timings.update_aabbs);

        let pairs = stages::broad_phase(&mut self.sap, &aabbs, &self.bodies);
        lap(&mut timings.broad_phase);

        let ids: Vec<u64> = self
            .handles
            .handles()
            .iter()
            .map(BodyHandle::to_bits)
            .collect();
        let narrow = stages::narrow_phase(
            &self.bodies,
            &self.states,
            &pairs,
            &ids,
            &self.cache,
            self.config.margin,
            dt,
        );
        let (mut contacts, keys) = (narrow.contacts, narrow.keys);
        lap(&mut timings.narrow_phase);

        let coloring = stages::color(
            &contacts,
            &self.bodies,
            self.config.solver.order,
            &self.config.gravity,
        );
        lap(&mut timings.color);

        let solved = stages::solve_with_effects(
            &self.bodies,
            &mut self.states,
            &mut contacts,
            &coloring,
            &self.config.solver,
            dt,
            &self.config.gravity,
            &effects,
        );
        lap(&mut timings.solve);

        stages::finish(
            &mut self.bodies,
            &mut self.states,
            &mut self.cache,
            &keys,
            &contacts,
        );
        lap(&mut timings.finish);

        self.stats = StepStats {
            bodies: self.bodies.len(),
            pairs: pairs.len(),
            manifolds: contacts.len(),
            contact_points: solved.points,
            colors: coloring.used_colors(),
            overflow: if coloring.colors.is_empty() {
                0
            } else {
                coloring.overflow_count()
            },
            parallel_colors: solved.parallel_batches,
            max_penetration: contacts
                .iter()
                .map(|c| c.manifold.max_depth())
                .fold(0.0, Real::max),
            timings,
        };
        let handles = self.handles.handles();
        self.contact_handles = contacts
            .iter()
            .map(|c| (handles[c.body_a as usize], handles[c.body_b as usize]))
            .collect();
        self.contacts = contacts;
        if effects.sleep {
            self.update_sleep(&effects);
        }
        self.steps += 1;
        Ok(())
    }

    /// Counts and per-stage timings of the last step.
    pub fn stats(&self) -> &StepStats {
        self.last_stats()
    }

    /// Pairs of bodies touching in the last step: some point overlapped at the start of the
    /// step, or pushed (a speculative point that caught an approaching body).
    pub fn contact_pairs(&self) -> Vec<(BodyHandle, BodyHandle)> {
        let (contacts, handles) = self.last_contacts();
        contacts
            .iter()
            .zip(handles)
            .filter(|(c, _)| c.is_touching())
            .map(|(_, h)| *h)
            .collect()
    }

    /// Every manifold of the last step, touching or speculative, by handle.
    pub fn contacts(&self) -> Vec<ContactReport> {
        let (contacts, handles) = self.last_contacts();
        contacts
            .iter()
            .zip(handles)
            .map(|(c, &(a, b))| ContactReport {
                body_a: a,
                body_b: b,
                normal: c.manifold.normal,
                kind: c.manifold.kind,
                feature: c.manifold.feature,
                points: c
                    .manifold
                    .points()
                    .iter()
                    .zip(&c.total_normal_impulse)
                    .map(|(p, &j)| ContactPointReport {
                        position: p.position,
                        depth: p.depth,
                        normal_impulse: j,
                        id: p.id,
                    })
                    .collect(),
            })
            .collect()
    }

    /// The deepest overlap among last step's manifolds, m (0 when nothing overlaps).
    pub fn max_penetration(&self) -> Real {
        self.last_stats().max_penetration
    }

    /// Drops last step's contacts that involve `removed`, keeping the rest by handle (the host
    /// arrays must be up to date: see `sync_all`).
    pub(crate) fn forget_contacts_of(&mut self, removed: BodyHandle) {
        let keep: Vec<bool> = self
            .contact_handles
            .iter()
            .map(|&(a, b)| a != removed && b != removed)
            .collect();
        let mut k = keep.iter();
        self.contacts.retain(|_| *k.next().unwrap_or(&false));
        let mut k = keep.iter();
        self.contact_handles.retain(|_| *k.next().unwrap_or(&false));
        self.cache.forget_body(removed.to_bits());
    }
}
