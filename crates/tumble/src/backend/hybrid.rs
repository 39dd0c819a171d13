//! `Backend::Hybrid`: the collision stages on the GPU ([`HybridCollision`]), then the CPU's
//! color, solve, finish and sleep stages ([`pipeline::step`]) on the manifolds it reads back;
//! the solved impulses go back to the GPU, whose matching warm starts the next step by
//! feature id.

use tumble_broad::is_wanted_pair;
use tumble_gpu::collision::CollisionConfig;
use tumble_gpu::step::HybridCollision;
use tumble_solver::{Body, Contact, PairKey, Stage, stages};

use super::pipeline::{self, Collided, Collision, StepBodies};
use super::{Host, StepArgs, StepBackend, shared_context, unavailable};
use crate::snapshot::{BackendSnapshot, corrupt_device, wrong_backend};
use crate::stats::StageClock;
use crate::{Backend, BodyHandle, Error, WorldConfig};

/// The GPU collision stages for the CPU pipeline.
#[derive(Debug)]
pub(crate) struct GpuCollision {
    collision: HybridCollision,
    /// The handles of the bodies on the GPU, in dense order: a different list means bodies
    /// were added or removed since, and everything is uploaded again.
    uploaded: Vec<BodyHandle>,
    /// The GPU pair slot of each manifold of the last [`Collision::collide`].
    slots: Vec<u32>,
    /// Last step's candidate pairs from the broad phase, by handle.
    pairs: Vec<(BodyHandle, BodyHandle)>,
}

fn failed(e: tumble_gpu::GpuError) -> Error {
    unavailable(Backend::Hybrid, e)
}

impl Collision for GpuCollision {
    fn collide(
        &mut self,
        step: &StepBodies<'_>,
        clock: &mut StageClock,
    ) -> Result<Collided, Error> {
        if self.uploaded != step.handles {
            self.collision.invalidate();
            self.uploaded = step.handles.to_vec();
        }
        // The GPU holds every body in dense order, sleepers included (at rest, as the
        // gathered copy has them); their pairs are filtered here as the CPU broad phase
        // filters the gathered bodies, sleepers counting as immovable.
        let found = self
            .collision
            .collide(step.dense_bodies, step.dense_states)
            .map_err(failed)?;
        let pairs = found.len();
        let immovable = step.gathered.map(|g| stages::immovable(&g.bodies));
        // The pairs with a sleeper are dropped as the manifolds are below.
        self.pairs = self
            .collision
            .pairs()
            .iter()
            .filter(|&&(a, b)| match (step.gathered, &immovable) {
                (Some(g), Some(immovable)) => {
                    is_wanted_pair(immovable, g.position(a as usize), g.position(b as usize))
                }
                _ => true,
            })
            .map(|&(a, b)| (step.handles[a as usize], step.handles[b as usize]))
            .collect();
        let mut out = Collided {
            pairs,
            ..Default::default()
        };
        self.slots.clear();
        for (slot, mut c) in found {
            let (a, b) = (c.body_a as usize, c.body_b as usize);
            if let (Some(g), Some(immovable)) = (step.gathered, &immovable) {
                let (ga, gb) = (g.position(a), g.position(b));
                if !is_wanted_pair(immovable, ga, gb) {
                    continue;
                }
                (c.body_a, c.body_b) = (ga, gb);
            }
            out.keys
                .push((step.handles[a].to_bits(), step.handles[b].to_bits()));
            out.contacts.push(c);
            self.slots.push(slot);
        }
        // The GPU's three collision stages are timed as one.
        clock.lap(Stage::NarrowPhase);
        Ok(out)
    }

    fn keep_impulses(
        &mut self,
        _keys: &[PairKey],
        contacts: &[Contact],
        solved: usize,
        _bodies: &[Body],
    ) -> Result<(), Error> {
        let back: Vec<(u32, Contact)> = self
            .slots
            .iter()
            .copied()
            .zip(contacts[..solved].iter().copied())
            .collect();
        self.collision.store_impulses(&back).map_err(failed)
    }
}

/// `Backend::Hybrid`: [`pipeline::step`] with [`GpuCollision`]; every result lives on the
/// host, so the reads and writes are the host's.
#[derive(Debug)]
pub(crate) struct HybridBackend {
    collision: GpuCollision,
}

impl HybridBackend {
    /// The GPU collision stages for `config`. Errs when no GPU is available.
    pub(crate) fn new(config: &WorldConfig) -> Result<Self, Error> {
        let ctx = shared_context().map_err(|e| unavailable(Backend::Hybrid, e))?;
        let collision = HybridCollision::new(
            &ctx,
            CollisionConfig {
                margin: config.margin,
                dt: config.dt,
                recycle_distance: config.recycle_distance,
                ..Default::default()
            },
        )
        .map_err(failed)?;
        Ok(Self {
            collision: GpuCollision {
                collision,
                uploaded: Vec::new(),
                slots: Vec::new(),
                pairs: Vec::new(),
            },
        })
    }
}

impl StepBackend for HybridBackend {
    fn kind(&self) -> Backend {
        Backend::Hybrid
    }

    fn step(&mut self, host: &mut Host, args: StepArgs<'_>) -> Result<(), Error> {
        let before = std::mem::take(&mut self.collision.pairs);
        let stepped = pipeline::step(host, args, &mut self.collision);
        if stepped.is_err() {
            self.collision.pairs = before;
        }
        stepped
    }

    fn broad_phase_pairs(&self) -> &[(BodyHandle, BodyHandle)] {
        &self.collision.pairs
    }

    fn save(&self) -> Result<BackendSnapshot, Error> {
        let collision = self.collision.collision.save_state().map_err(failed)?;
        Ok(BackendSnapshot::Hybrid {
            collision: Box::new(collision),
            uploaded: self.collision.uploaded.clone(),
        })
    }

    fn load(&mut self, saved: &BackendSnapshot, host: &Host) -> Result<(), Error> {
        let BackendSnapshot::Hybrid {
            collision,
            uploaded,
        } = saved
        else {
            return Err(wrong_backend(saved, self.kind()));
        };
        let _ = host;
        if collision.collision.body_count as usize != uploaded.len()
            && collision.collision.body_count != 0
        {
            return Err(corrupt_device(format!(
                "{} bodies on the GPU, {} handles",
                collision.collision.body_count,
                uploaded.len()
            )));
        }
        self.collision
            .collision
            .load_state(collision)
            .map_err(corrupt_device)?;
        self.collision.uploaded = uploaded.clone();
        Ok(())
    }

    fn device_buffer_bytes(&self) -> u64 {
        self.collision.collision.buffer_bytes()
    }
}
