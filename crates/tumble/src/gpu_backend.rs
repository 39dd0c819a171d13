//! `Backend::Gpu` and `Backend::Hybrid`: the world's step on the GPU through
//! `tumble_gpu::step`.
//!
//! The world keeps its host arrays (bodies, states, contacts) as the source of truth between
//! steps, so every getter, setter and check of the facade works unchanged:
//! - `Backend::Gpu` runs the whole step on the GPU ([`GpuWorld`]). Before a step, bodies
//!   added or removed since the last one cause a full upload, and poses or velocities the user
//!   set are written to the GPU; after it, poses, velocities and contacts come back in the
//!   step's own command stream (one submit, one wait).
//! - `Backend::Hybrid` runs the collision stages on the GPU ([`HybridCollision`]) and the CPU
//!   `color`, `solve` and `finish` stages on the manifolds it reads back; the solved impulses go
//!   back to the GPU, whose matching warm starts the next step by feature id.

use std::sync::OnceLock;
use std::time::{Duration, Instant};

use tumble_geometry::{Pose, Real};
use tumble_gpu::collision::CollisionConfig;
use tumble_gpu::solver::Effects as GpuEffects;
use tumble_gpu::step::{GpuWorld, GpuWorldConfig, HybridCollision, ReadRequest};
use tumble_gpu::{GpuContext, GpuError};
use tumble_solver::{BodyState, Contact, finalize_bodies};

use crate::{Backend, BodyHandle, Error, StageTimings, StepStats, World, WorldConfig, stages};

/// One device for every GPU world of the process: opening a device and compiling pipelines
/// is the slow part of starting a world, and pipelines are shared per device.
fn shared_context() -> Result<GpuContext, String> {
    static SHARED: OnceLock<Result<GpuContext, String>> = OnceLock::new();
    SHARED
        .get_or_init(|| GpuContext::new().map_err(|e| e.to_string()))
        .clone()
}

fn unavailable(backend: Backend, e: impl std::fmt::Display) -> Error {
    Error::BackendUnavailable {
        backend,
        reason: e.to_string(),
    }
}

/// The GPU side of a world.
#[derive(Debug)]
pub(crate) enum GpuBackend {
    /// The whole step on the GPU.
    Gpu(Box<GpuStep>),
    /// Collision on the GPU, solver on the CPU.
    Hybrid(Box<HybridStep>),
}

/// State of `Backend::Gpu`.
#[derive(Debug)]
pub(crate) struct GpuStep {
    gpu: GpuWorld,
    /// The handles of the bodies on the GPU, in dense order: a different list means bodies
    /// were added or removed since, and everything is uploaded again.
    uploaded: Vec<BodyHandle>,
    /// Pose and velocities of each body as the GPU has them; a host value that differs was
    /// set by the user and is written to the GPU before the next step.
    synced: Vec<(Pose, BodyState)>,
}

/// State of `Backend::Hybrid`.
#[derive(Debug)]
pub(crate) struct HybridStep {
    collision: HybridCollision,
    uploaded: Vec<BodyHandle>,
}

impl GpuBackend {
    /// The GPU side for `config.backend`; `None` for `Backend::Cpu`.
    pub(crate) fn new(config: &WorldConfig) -> Result<Option<Self>, Error> {
        let backend = config.backend;
        if backend == Backend::Cpu {
            return Ok(None);
        }
        let ctx = shared_context().map_err(|e| unavailable(backend, e))?;
        let fail = |e: GpuError| unavailable(backend, e);
        Ok(Some(match backend {
            Backend::Cpu => unreachable!("returned above"),
            Backend::Gpu => {
                let gpu = GpuWorld::new(
                    &ctx,
                    GpuWorldConfig {
                        gravity: config.gravity,
                        dt: config.dt,
                        margin: config.margin,
                        solver: config.solver,
                        timestamps: ctx.has_timestamps,
                        ..Default::default()
                    },
                )
                .map_err(fail)?;
                GpuBackend::Gpu(Box::new(GpuStep {
                    gpu,
                    uploaded: Vec::new(),
                    synced: Vec::new(),
                }))
            }
            Backend::Hybrid => {
                let collision = HybridCollision::new(
                    &ctx,
                    CollisionConfig {
                        margin: config.margin,
                        dt: config.dt,
                        ..Default::default()
                    },
                )
                .map_err(fail)?;
                GpuBackend::Hybrid(Box::new(HybridStep {
                    collision,
                    uploaded: Vec::new(),
                }))
            }
        }))
    }
}

/// GPU stage times (timestamps) folded into the facade's stages.
fn gpu_timings(stages: &[(&'static str, f64)]) -> StageTimings {
    let mut t = StageTimings::default();
    for &(name, seconds) in stages {
        let d = Duration::from_secs_f64(seconds);
        match name {
            "update_aabbs" => t.update_aabbs += d,
            "broad_phase" => t.broad_phase += d,
            "narrow_phase" => t.narrow_phase += d,
            "color" => t.color += d,
            "finish" => t.finish += d,
            // prepare, the substeps, the fused kernel, queued impulses.
            _ => t.solve += d,
        }
    }
    t
}

fn max_penetration(contacts: &[Contact]) -> Real {
    contacts
        .iter()
        .map(|c| c.manifold.max_depth())
        .fold(0.0, Real::max)
}

impl World {
    /// One step on the GPU backend, returning its statistics; `None` on `Backend::Cpu`.
    pub(crate) fn step_on_gpu(&mut self) -> Result<Option<StepStats>, Error> {
        let backend = self.config.backend;
        if self.gpu.is_none() {
            return Ok(None);
        }
        // The effects the step runs, with the config's overrides; sleep is not on the GPU
        // backends (no islands there), so bodies never sleep on them.
        let effects = self.effects();
        let Some(gpu) = self.gpu.as_mut() else {
            return Ok(None);
        };
        let fail = |e: GpuError| unavailable(backend, e);
        let handles = self.handles.handles().to_vec();
        let stats = match gpu {
            GpuBackend::Gpu(state) => {
                let clock = Instant::now();
                let gpu = &mut state.gpu;
                if state.uploaded != handles {
                    gpu.set_bodies(&self.bodies, &self.states).map_err(fail)?;
                    state.uploaded = handles.clone();
                } else {
                    for (i, (body, s)) in self.bodies.iter().zip(&self.states).enumerate() {
                        let (pose, synced) = &state.synced[i];
                        if body.pose != *pose {
                            gpu.set_pose(i, &body.pose).map_err(fail)?;
                        }
                        if s.linear_velocity != synced.linear_velocity
                            || s.angular_velocity != synced.angular_velocity
                        {
                            gpu.set_velocity(i, &s.linear_velocity, &s.angular_velocity)
                                .map_err(fail)?;
                        }
                    }
                }
                gpu.set_effects(GpuEffects::from(&effects)).map_err(fail)?;
                gpu.request_reads(ReadRequest::ALL);
                gpu.step().map_err(fail)?;
                let mut snapshot = gpu
                    .wait_snapshot()
                    .map_err(fail)?
                    .ok_or_else(|| unavailable(backend, "the step's readback was not recorded"))?;
                let truncated = snapshot
                    .contacts
                    .as_ref()
                    .is_some_and(|c| c.work.count as usize > c.manifolds.len());
                if truncated {
                    snapshot.contacts = gpu.read_now(ReadRequest::ALL).map_err(fail)?.contacts;
                }
                for (i, (body, s)) in self.bodies.iter_mut().zip(&mut self.states).enumerate() {
                    body.pose = snapshot.pose(i);
                    *s = snapshot.state(i);
                }
                state.synced = self
                    .bodies
                    .iter()
                    .zip(&self.states)
                    .map(|(b, s)| (b.pose, *s))
                    .collect();
                let contact_set = snapshot.contacts.unwrap_or_default();
                let pairs = contact_set.work.count as usize;
                self.contacts = contact_set.contacts();
                let mut timings = gpu_timings(&gpu.timings().map_err(fail)?);
                if timings.total().is_zero() {
                    timings.solve = clock.elapsed();
                }
                StepStats {
                    bodies: self.bodies.len(),
                    pairs,
                    manifolds: self.contacts.len(),
                    contact_points: self.contacts.iter().map(|c| c.manifold.len as usize).sum(),
                    max_penetration: max_penetration(&self.contacts),
                    timings,
                    ..Default::default()
                }
            }
            GpuBackend::Hybrid(state) => {
                let mut timings = StageTimings::default();
                let clock = Instant::now();
                if state.uploaded != handles {
                    state.collision.invalidate();
                    state.uploaded = handles.clone();
                }
                let found = state
                    .collision
                    .collide(&self.bodies, &self.states)
                    .map_err(fail)?;
                timings.narrow_phase = clock.elapsed();
                let (slots, mut contacts): (Vec<u32>, Vec<Contact>) = found.into_iter().unzip();
                let clock = Instant::now();
                let coloring = stages::color(&contacts, &self.bodies, self.config.solver.order);
                timings.color = clock.elapsed();
                let clock = Instant::now();
                let solved = stages::solve_with_effects(
                    &self.bodies,
                    &mut self.states,
                    &mut contacts,
                    &coloring,
                    &self.config.solver,
                    self.config.dt,
                    &self.config.gravity,
                    &effects,
                );
                timings.solve = clock.elapsed();
                let clock = Instant::now();
                finalize_bodies(&mut self.bodies, &mut self.states);
                let back: Vec<(u32, Contact)> =
                    slots.into_iter().zip(contacts.iter().copied()).collect();
                state.collision.store_impulses(&back).map_err(fail)?;
                timings.finish = clock.elapsed();
                self.contacts = contacts;
                StepStats {
                    bodies: self.bodies.len(),
                    pairs: self.contacts.len(),
                    manifolds: self.contacts.len(),
                    contact_points: solved.points,
                    colors: coloring.used_colors(),
                    overflow: if coloring.colors.is_empty() {
                        0
                    } else {
                        coloring.overflow_count()
                    },
                    parallel_colors: solved.parallel_batches,
                    max_penetration: max_penetration(&self.contacts),
                    timings,
                }
            }
        };
        self.contact_handles = self
            .contacts
            .iter()
            .map(|c| (handles[c.body_a as usize], handles[c.body_b as usize]))
            .collect();
        Ok(Some(stats))
    }
}
