//! `Backend::Gpu` and `Backend::Hybrid`: the world's step on the GPU through
//! `tumble_gpu::step`.
//!
//! - `Backend::Gpu` runs the whole step on the GPU ([`GpuWorld`]) and does not wait for it:
//!   the GPU holds the state, and the host arrays (bodies, states, contacts) are a copy that
//!   may be behind. Getters read the step's results lazily ([`crate::gpu_reads`]): only what
//!   is asked for crosses the bus, from a staging copy recorded with the step when the caller
//!   read that part after the previous step. A call that changes the world first brings the
//!   host arrays up to date (poses and velocities; contacts too when bodies are added or
//!   removed); the next step then writes to the GPU only what the caller changed, or
//!   everything when bodies were added or removed.
//! - `Backend::Hybrid` runs the collision stages on the GPU ([`HybridCollision`]) and the CPU
//!   `color`, `solve` and `finish` stages on the manifolds it reads back; the solved impulses go
//!   back to the GPU, whose matching warm starts the next step by feature id.

use std::sync::{Mutex, OnceLock};
use std::time::Instant;

use tumble_geometry::Pose;
use tumble_gpu::collision::CollisionConfig;
use tumble_gpu::solver::Effects as GpuEffects;
use tumble_gpu::step::{GpuWorld, GpuWorldConfig, HybridCollision};
use tumble_gpu::{GpuContext, GpuError};
use tumble_solver::{BodyState, Contact, finalize_bodies};

use crate::gpu_reads::{ContactView, Reads, Unread, max_penetration};
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
    /// Locked only by getters reading results; a step has `&mut` access.
    gpu: Mutex<GpuWorld>,
    /// The handles of the bodies on the GPU, in dense order: a different list means bodies
    /// were added or removed since, and everything is uploaded again.
    uploaded: Vec<BodyHandle>,
    /// Pose and velocities of each body as the GPU had them when the host arrays were last
    /// brought up to date; a host value that differs was set by the user and is written to
    /// the GPU before the next step.
    synced: Vec<(Pose, BodyState)>,
    /// The last step's results, until the host has them all.
    unread: Option<Unread>,
    /// What the caller read after the step before the one in `unread` (or after the last
    /// step, once `unread` is gone).
    last_asked: Reads,
}

impl GpuStep {
    /// What the caller read after the last step: the `Auto` readbacks of the next one.
    fn asked(&self) -> Reads {
        self.unread.as_ref().map_or(self.last_asked, Unread::asked)
    }
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
                    gpu: Mutex::new(gpu),
                    uploaded: Vec::new(),
                    synced: Vec::new(),
                    unread: None,
                    last_asked: Reads::default(),
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

fn poisoned(backend: Backend) -> Error {
    unavailable(backend, "the GPU world's lock was poisoned by a panic")
}

impl World {
    /// One step on the GPU backend, returning its statistics; `None` on `Backend::Cpu`.
    pub(crate) fn step_on_gpu(&mut self) -> Result<Option<StepStats>, Error> {
        let backend = self.config.backend;
        if self.gpu.is_none() {
            return Ok(None);
        }
        // The effects the step runs, with the config's overrides. Sleep runs on the GPU
        // itself on `Backend::Gpu`; `Backend::Hybrid` has no islands.
        let effects = self.effects();
        let Some(gpu) = self.gpu.as_mut() else {
            return Ok(None);
        };
        let fail = |e: GpuError| unavailable(backend, e);
        let handles = self.handles.handles().to_vec();
        let stats = match gpu {
            GpuBackend::Gpu(state) => {
                if let Some(e) = state.unread.as_ref().and_then(Unread::error) {
                    return Err(unavailable(backend, e));
                }
                let asked = state.asked();
                let host_current = state.unread.as_ref().is_none_or(|u| u.motion_in_host);
                let gpu = state.gpu.get_mut().map_err(|_| poisoned(backend))?;
                if state.uploaded != handles {
                    // Adding or removing a body brought the host arrays up to date first.
                    debug_assert!(host_current, "bodies changed while the host was behind");
                    gpu.set_bodies(&self.bodies, &self.states).map_err(fail)?;
                    state.uploaded = handles.clone();
                } else if host_current {
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
                // Otherwise the caller changed nothing since the last step: every change
                // brings the host arrays up to date first.
                gpu.set_effects(GpuEffects::from(&effects)).map_err(fail)?;
                let mut reads = self.config.effects.readback.resolve(asked);
                reads.sleeping &= effects.sleep;
                gpu.request_reads(reads.request());
                gpu.step().map_err(fail)?;
                state.last_asked = asked;
                state.unread = Some(Unread::new(gpu.steps(), handles.clone(), reads));
                // The counts and times come from the step's results, read when asked for.
                StepStats {
                    bodies: self.bodies.len(),
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
                let coloring = stages::color(
                    &contacts,
                    &self.bodies,
                    self.config.solver.order,
                    &self.config.gravity,
                );
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
        if !matches!(self.gpu, Some(GpuBackend::Gpu(_))) {
            self.contact_handles = self
                .contacts
                .iter()
                .map(|c| (handles[c.body_a as usize], handles[c.body_b as usize]))
                .collect();
        }
        Ok(Some(stats))
    }
}

/// The last GPU step's unread results and the world they are read from.
type UnreadStep<'a> = (&'a Mutex<GpuWorld>, &'a Unread);

impl World {
    /// Bytes of results `Backend::Gpu` copied from the GPU to the host so far: only what the
    /// caller read (see [`crate::ReadbackOverrides`]). 0 on the other backends, which hold
    /// their results on the host (`Backend::Hybrid` reads every manifold for its CPU solver).
    pub fn readback_bytes(&self) -> u64 {
        match self.gpu.as_ref() {
            Some(GpuBackend::Gpu(state)) => state.gpu.lock().map_or(0, |g| g.bytes_read()),
            Some(GpuBackend::Hybrid(_)) | None => 0,
        }
    }

    /// The last `Backend::Gpu` step's results, when the host arrays do not hold them.
    fn unread(&self) -> Option<UnreadStep<'_>> {
        match self.gpu.as_ref()? {
            GpuBackend::Gpu(state) => state.unread.as_ref().map(|u| (&state.gpu, u)),
            GpuBackend::Hybrid(_) => None,
        }
    }

    /// Same, when the host arrays do not hold its poses and velocities either.
    fn unread_motion(&self) -> Option<UnreadStep<'_>> {
        self.unread().filter(|(_, u)| !u.motion_in_host)
    }

    /// The pose of the body at dense index `d` now.
    pub(crate) fn pose_at(&self, d: usize) -> Result<Pose, Error> {
        match self.unread_motion() {
            Some((gpu, u)) => u
                .poses(gpu)
                .map(|p| p[d])
                .map_err(|e| unavailable(self.config.backend, e)),
            None => Ok(self.bodies[d].pose),
        }
    }

    /// The velocities of the body at dense index `d` now.
    pub(crate) fn state_at(&self, d: usize) -> Result<BodyState, Error> {
        match self.unread_motion() {
            Some((gpu, u)) => u
                .velocities(gpu)
                .map(|v| v[d])
                .map_err(|e| unavailable(self.config.backend, e)),
            None => Ok(self.states[d]),
        }
    }

    /// Which bodies sleep on `Backend::Gpu` (read lazily); `None` on the other backends.
    pub(crate) fn gpu_sleeping(&self) -> Result<Option<&[bool]>, Error> {
        let Some(GpuBackend::Gpu(state)) = self.gpu.as_ref() else {
            return Ok(None);
        };
        match state.unread.as_ref() {
            Some(u) if self.effects().sleep => u
                .sleeping(&state.gpu)
                .map(Some)
                .map_err(|e| unavailable(self.config.backend, e)),
            // Before any step, with sleep off, or once bodies were added or removed (which
            // wakes every body on the GPU), nothing sleeps: the host's awake state says so.
            _ => Ok(None),
        }
    }

    /// Wakes the island of the body at dense index `d` on `Backend::Gpu` before the next step.
    pub(crate) fn wake_on_gpu(&mut self, d: usize) -> Result<(), Error> {
        let backend = self.config.backend;
        if let Some(GpuBackend::Gpu(state)) = self.gpu.as_mut() {
            let gpu = state.gpu.get_mut().map_err(|_| poisoned(backend))?;
            gpu.wake_up(d).map_err(|e| unavailable(backend, e))?;
        }
        Ok(())
    }

    /// Last step's manifolds and the handles of their bodies. A failed GPU read reports no
    /// contacts here and its error from the next step.
    pub(crate) fn last_contacts(&self) -> (&[Contact], &[(BodyHandle, BodyHandle)]) {
        match self.unread().map(|(gpu, u)| u.contacts(gpu)) {
            Some(Ok(ContactView {
                contacts, handles, ..
            })) => (contacts, handles),
            Some(Err(_)) => (&[], &[]),
            None => (&self.contacts, &self.contact_handles),
        }
    }

    /// Last step's statistics.
    pub(crate) fn last_stats(&self) -> &StepStats {
        match self.unread() {
            Some((gpu, u)) => u.stats(gpu),
            None => &self.stats,
        }
    }

    /// Brings the host's poses and velocities up to date with the GPU before a call changes
    /// them, so that the change is made to the current state and the next step uploads it.
    pub(crate) fn sync_motion(&mut self) -> Result<(), Error> {
        let backend = self.config.backend;
        let Some(GpuBackend::Gpu(state)) = self.gpu.as_mut() else {
            return Ok(());
        };
        let Some(u) = state.unread.as_mut().filter(|u| !u.motion_in_host) else {
            return Ok(());
        };
        let fail = |e: String| unavailable(backend, e);
        let poses = u.poses(&state.gpu).map_err(fail)?;
        let velocities = u.velocities(&state.gpu).map_err(fail)?;
        for ((body, s), (pose, v)) in self
            .bodies
            .iter_mut()
            .zip(&mut self.states)
            .zip(poses.iter().zip(velocities))
        {
            body.pose = *pose;
            *s = *v;
        }
        state.synced = poses
            .iter()
            .copied()
            .zip(velocities.iter().copied())
            .collect();
        u.motion_in_host = true;
        Ok(())
    }

    /// Brings every host array up to date with the GPU (before bodies are added or removed,
    /// which renumbers them).
    pub(crate) fn sync_all(&mut self) -> Result<(), Error> {
        self.sync_motion()?;
        let backend = self.config.backend;
        let Some(GpuBackend::Gpu(state)) = self.gpu.as_mut() else {
            return Ok(());
        };
        let Some(u) = state.unread.take() else {
            return Ok(());
        };
        let view = u.contacts(&state.gpu);
        let result = view.map(|view| {
            self.contacts = view.contacts.clone();
            self.contact_handles = view.handles.clone();
            self.stats = *u.stats(&state.gpu);
        });
        state.last_asked = u.asked();
        if let Err(e) = result {
            state.unread = Some(u);
            return Err(unavailable(backend, e));
        }
        Ok(())
    }
}
