//! The world: bodies, configuration, and the step, run by the world's backend.

use tumble_geometry::Real;

use crate::backend::{Host, StepArgs, StepBackend, new_backend};
use crate::events::EventState;
use crate::{
    BodyHandle, ContactEvent, ContactPointReport, ContactReport, Error, StepStats, TouchingPair,
    WorldConfig, handle::HandleMap, query::QueryCache,
};

/// A simulated world of boxes.
///
/// Bodies live in dense arrays (cold [`tumble_solver::Body`] data and hot
/// [`tumble_solver::BodyState`]) addressed through [`BodyHandle`]s; the step runs the stages
/// of [`crate::stages::Stage::ALL`] on the backend of [`WorldConfig::backend`].
#[derive(Debug)]
pub struct World {
    pub(crate) config: WorldConfig,
    pub(crate) handles: HandleMap,
    /// The host copy of the bodies and of the last step's results.
    pub(crate) host: Host,
    /// Where the step runs, and how the state is read and written there.
    pub(crate) backend: Box<dyn StepBackend>,
    /// The spatial queries' tree over the current poses (`crate::query`), dropped by every
    /// call that moves, adds or removes a body.
    pub(crate) query: QueryCache,
    /// Contact events: on or off, last step's touching pairs and events (`crate::events`).
    pub(crate) events: EventState,
    pub(crate) steps: u64,
}

impl World {
    /// An empty world. Errs on a bad config (naming the field) or an unavailable backend.
    pub fn new(config: WorldConfig) -> Result<Self, Error> {
        config.validate()?;
        let backend = new_backend(&config)?;
        Self::with_backend(config, backend)
    }

    /// An empty world of `config` stepped by `backend` (`World::new`'s, or a GPU batch's
    /// member). Errs on a bad config, naming the field.
    pub(crate) fn with_backend(
        config: WorldConfig,
        backend: Box<dyn StepBackend>,
    ) -> Result<Self, Error> {
        config.validate()?;
        Ok(Self {
            config,
            handles: HandleMap::default(),
            host: Host::default(),
            backend,
            query: QueryCache::default(),
            events: EventState::default(),
            steps: 0,
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
        let effects = self.effects();
        self.query.invalidate();
        let args = StepArgs {
            handles: &self.handles,
            config: &self.config,
            effects: &effects,
        };
        self.backend.step(&mut self.host, args)?;
        self.query.stepped();
        self.steps += 1;
        if self.events.enabled {
            let (touching, events) = self.backend.touching_and_events(
                &self.host,
                &self.events.touching,
                effects.sleep,
            )?;
            self.events.update(touching, events);
        }
        Ok(())
    }

    /// Turns contact events on or off (off by default, when steps compute and read nothing
    /// for them). On, every step compares its touching pairs with the last step's (see
    /// [`World::contact_events`]); the first step after turning them on begins every pair
    /// touching then. Off forgets the touching pairs and events.
    ///
    /// `Backend::Gpu` compares the steps on the GPU and reads back only the events and the
    /// touching pairs, waiting for each step to finish; Errs only when the GPU cannot build
    /// the stage's kernels.
    pub fn set_contact_events(&mut self, on: bool) -> Result<(), Error> {
        self.backend.set_contact_events(on)?;
        self.events.set_enabled(on);
        Ok(())
    }

    /// Whether steps compute contact events.
    pub fn contact_events_enabled(&self) -> bool {
        self.events.enabled
    }

    /// The pairs that began or ended touching in the last step, sorted by body pair (smaller
    /// handle first); empty while events are off. A pair touches when its manifold has a
    /// point that overlapped at the start of the step or pushed during it (a speculative
    /// point that stayed apart does not count; see `crate::events`). A pair one of whose
    /// bodies was removed ends at the next step.
    pub fn contact_events(&self) -> &[ContactEvent] {
        &self.events.events
    }

    /// The pairs touching in the last step with their normal impulse and a contact point,
    /// sorted by body pair; empty while events are off.
    pub fn touching_pairs(&self) -> &[TouchingPair] {
        &self.events.touching
    }

    /// Counts and per-stage timings of the last step.
    pub fn stats(&self) -> &StepStats {
        self.backend.stats(&self.host)
    }

    /// Pairs of bodies touching in the last step: some point overlapped at the start of the
    /// step, or pushed (a speculative point that caught an approaching body).
    pub fn contact_pairs(&self) -> Vec<(BodyHandle, BodyHandle)> {
        let (contacts, handles) = self.backend.contacts(&self.host);
        contacts
            .iter()
            .zip(handles)
            .filter(|(c, _)| c.is_touching())
            .map(|(_, h)| *h)
            .collect()
    }

    /// Every manifold of the last step, touching or speculative, by handle.
    pub fn contacts(&self) -> Vec<ContactReport> {
        let (contacts, handles) = self.backend.contacts(&self.host);
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

    /// The solver's graph color of each manifold of [`World::contacts`], in its order:
    /// `Some(c)` with `c` below [`crate::solver::GRAPH_COLOR_COUNT`], or
    /// [`crate::solver::OVERFLOW_COLOR`] for the overflow set; `None` for a manifold the step
    /// did not color (a sleeping island's kept one). Empty when the last step colored nothing
    /// (`SolveOrder` sequential) and on `Backend::Gpu`, whose colors stay on the device
    /// (`World::gpu_contact_colors`).
    pub fn contact_colors(&self) -> Vec<Option<u32>> {
        let colored = |&c: &u32| (c <= crate::solver::OVERFLOW_COLOR).then_some(c);
        self.host.contact_colors.iter().map(colored).collect()
    }

    /// The candidate pairs the broad phase produced in the last step, touching or not: pairs
    /// of bodies whose AABBs (grown by the speculative margin and the step's motion)
    /// overlapped and that may collide (not both immovable, collision groups allowing), the
    /// body of the lower dense index first, sorted. [`World::contacts`] holds the pairs the
    /// narrow phase kept. Bodies removed since the step may appear. Empty before the first
    /// step, after a step in which nothing could move, and on `Backend::Gpu`, whose pair
    /// list stays on the device (there each manifold slot of `World::gpu_draw_buffers` is
    /// one candidate pair).
    pub fn broad_phase_pairs(&self) -> &[(BodyHandle, BodyHandle)] {
        self.backend.broad_phase_pairs()
    }

    /// The deepest overlap among last step's manifolds, m (0 when nothing overlaps).
    pub fn max_penetration(&self) -> Real {
        self.stats().max_penetration
    }

    /// Bytes of results `Backend::Gpu` copied from the GPU to the host so far: only what the
    /// caller read (see [`crate::ReadbackOverrides`]). 0 on the other backends, which hold
    /// their results on the host (`Backend::Hybrid` reads every manifold for its CPU solver).
    pub fn readback_bytes(&self) -> u64 {
        self.backend.readback_bytes()
    }

    /// Bytes of GPU buffers the world holds now: on `Backend::Gpu` every stage's pooled
    /// buffers, on `Backend::Hybrid` the collision stages'; 0 on `Backend::Cpu`. Buffers
    /// grow with the scene and are kept, so a world whose body count stays bounded holds a
    /// bounded amount (`cargo xtask soak` samples it).
    pub fn device_buffer_bytes(&self) -> u64 {
        self.backend.device_buffer_bytes()
    }

    /// On `Backend::Gpu`, each GPU buffer behind [`Self::device_buffer_bytes`] as (pool,
    /// buffer name, bytes): the stages' pools and the step check's shadow copies
    /// (`tumble_gpu::step::GpuWorld::buffer_sizes`; docs/gpu.md, "Memory per body"). Empty on
    /// the other backends.
    pub fn device_buffer_sizes(&self) -> Vec<(&'static str, &'static str, u64)> {
        self.backend.device_buffer_sizes()
    }

    /// Drops last step's contacts that involve `removed`, keeping the rest by handle (the host
    /// arrays must be up to date: see `StepBackend::sync_all`).
    pub(crate) fn forget_contacts_of(&mut self, removed: BodyHandle) {
        let host = &mut self.host;
        let keep: Vec<bool> = host
            .contact_handles
            .iter()
            .map(|&(a, b)| a != removed && b != removed)
            .collect();
        let mut k = keep.iter();
        host.contacts.retain(|_| *k.next().unwrap_or(&false));
        let mut k = keep.iter();
        host.contact_handles.retain(|_| *k.next().unwrap_or(&false));
        let mut k = keep.iter();
        host.contact_colors.retain(|_| *k.next().unwrap_or(&false));
        self.backend.forget_body(removed.to_bits());
    }
}
