//! `Backend::Gpu`: the whole step on the GPU ([`GpuWorld`]), not waited for.
//!
//! The GPU holds the state, and the host arrays (bodies, states, contacts) are a copy that
//! may be behind. Reads take the step's results lazily ([`crate::gpu_reads`]): only what is
//! asked for crosses the bus, from a staging copy recorded with the step when the caller read
//! that part after the previous step. A call that changes the world first brings the host
//! arrays up to date ([`StepBackend::sync_motion`], [`StepBackend::sync_all`]); the next step
//! then writes to the GPU only what the caller changed, or everything when bodies were added
//! or removed. Islands are found and put to sleep on the GPU (`tumble_gpu::sleep`, label
//! propagation with the CPU's thresholds).

use std::sync::{Mutex, OnceLock};

use tumble_geometry::{Point3, Pose};
use tumble_gpu::kernels::contact_events::{EVENT_BEGIN, EVENT_END};
use tumble_gpu::layout::GpuContactEvent;
use tumble_gpu::step::{GpuWorld, GpuWorldConfig};
use tumble_solver::{BodyKind, BodyState, bounds};

use super::{
    ContactsView, Host, StepArgs, StepBackend, TouchingAndEvents, shared_context, unavailable,
};
use crate::gpu_reads::{ContactView, Reads, Unread};
use crate::snapshot::{BackendSnapshot, corrupt_device, wrong_backend};
use crate::{
    Backend, BodyHandle, ContactEvent, ContactEventKind, Error, StepStats, TouchingPair,
    WorldConfig,
};

mod check;

pub(crate) use check::check_results;

fn failed(e: impl std::fmt::Display) -> Error {
    unavailable(Backend::Gpu, e)
}

fn poisoned() -> Error {
    failed("the GPU world's lock was poisoned by a panic")
}

/// The device world's settings for a world of `config` on `ctx` (timestamps where the
/// device has them), for `Backend::Gpu` and the GPU batch's groups alike.
pub(crate) fn gpu_world_config(
    config: &WorldConfig,
    ctx: &tumble_gpu::GpuContext,
) -> GpuWorldConfig {
    GpuWorldConfig {
        gravity: config.gravity,
        dt: config.dt,
        margin: config.margin,
        recycle_distance: config.recycle_distance,
        solver: config.solver,
        timestamps: ctx.has_timestamps,
        ..Default::default()
    }
}

/// State of `Backend::Gpu`.
#[derive(Debug)]
pub(crate) struct GpuBackend {
    /// Locked only by reads; a step has `&mut` access.
    gpu: Mutex<GpuWorld>,
    /// The handles of the bodies on the GPU, in dense order: a different list means bodies
    /// were added or removed since, and everything is uploaded again.
    uploaded: Vec<BodyHandle>,
    /// Pose and velocities of each body as the GPU had them when the host arrays were last
    /// brought up to date; a host value that differs was set by the user and is written to
    /// the GPU before the next step.
    synced: Vec<(Pose, BodyState)>,
    /// Dense indices of the bodies whose groups, force, torque or gravity scale changed in
    /// the host copy since the last step: written to the GPU before the next one.
    changed: Vec<usize>,
    /// The last step's results, until the host has them all.
    unread: Option<Unread>,
    /// What the caller read after the step before the one in `unread` (or after the last
    /// step, once `unread` is gone).
    last_asked: Reads,
    /// The first body state out of bounds that a step left, once found (by a read, which
    /// has `&self`): every later step and write returns it.
    invalid: OnceLock<Error>,
    /// Whether the last step uploaded every body again (bodies were added or removed): the
    /// GPU's comparison of its pairs with the step before's, by dense index, is then void.
    uploaded_last_step: bool,
}

impl GpuBackend {
    /// The GPU world for `config`. Errs when no GPU is available.
    pub(crate) fn new(config: &WorldConfig) -> Result<Self, Error> {
        let ctx = shared_context().map_err(failed)?;
        let gpu = GpuWorld::new(&ctx, gpu_world_config(config, &ctx)).map_err(failed)?;
        let mut gpu = gpu;
        gpu.set_motion_check(true).map_err(failed)?;
        Ok(Self {
            gpu: Mutex::new(gpu),
            uploaded: Vec::new(),
            synced: Vec::new(),
            changed: Vec::new(),
            unread: None,
            last_asked: Reads::default(),
            invalid: OnceLock::new(),
            uploaded_last_step: false,
        })
    }

    /// What the caller read after the last step: the `Auto` readbacks of the next one.
    fn asked(&self) -> Reads {
        self.unread.as_ref().map_or(self.last_asked, Unread::asked)
    }

    /// The error for body `d`'s state out of bounds, kept for every later step and write.
    fn found(&self, d: usize, e: bounds::StateViolation) -> Error {
        let e = Error::InvalidGpuState {
            body: self.uploaded[d],
            quantity: e.quantity,
            value: e.value,
            expected: e.expected,
        };
        let _ = self.invalid.set(e.clone());
        e
    }

    /// The pairs of `previous` (the step before's touching pairs) missing from `touching`
    /// whose two bodies are each asleep or not dynamic after the last step: the pairs at rest
    /// in a sleeping island, which the GPU did not collide.
    fn kept_asleep(
        &self,
        host: &Host,
        previous: &[TouchingPair],
        touching: &[TouchingPair],
    ) -> Result<Vec<TouchingPair>, Error> {
        let Some(unread) = self.unread.as_ref() else {
            return Ok(Vec::new());
        };
        if previous.is_empty() || self.uploaded_last_step {
            // Uploading every body again woke them all.
            return Ok(Vec::new());
        }
        // Most steps end no pair: then neither the sleep flags nor the dense indices are read.
        let now: std::collections::HashSet<(BodyHandle, BodyHandle)> =
            touching.iter().map(|p| (p.body_a, p.body_b)).collect();
        let missing: Vec<TouchingPair> = previous
            .iter()
            .filter(|p| !now.contains(&(p.body_a, p.body_b)))
            .copied()
            .collect();
        if missing.is_empty() {
            return Ok(missing);
        }
        let asleep = unread.sleeping(&self.gpu).map_err(failed)?;
        // Dense indices of the missing pairs' bodies only: one pass over the handles.
        let wanted: std::collections::HashSet<BodyHandle> =
            missing.iter().flat_map(|p| [p.body_a, p.body_b]).collect();
        let dense: std::collections::HashMap<BodyHandle, usize> = self
            .uploaded
            .iter()
            .enumerate()
            .filter(|(_, h)| wanted.contains(h))
            .map(|(d, &h)| (h, d))
            .collect();
        let rests = |h: &BodyHandle| {
            dense.get(h).is_some_and(|&d| {
                asleep.get(d).copied().unwrap_or(false)
                    || host
                        .bodies
                        .get(d)
                        .is_some_and(|b| b.kind != BodyKind::Dynamic)
            })
        };
        Ok(missing
            .into_iter()
            .filter(|p| rests(&p.body_a) && rests(&p.body_b))
            .collect())
    }

    /// The last step's results, when the host arrays do not hold its poses and velocities.
    fn unread_motion(&self) -> Option<&Unread> {
        self.unread.as_ref().filter(|u| !u.motion_in_host)
    }
}

impl StepBackend for GpuBackend {
    fn kind(&self) -> Backend {
        Backend::Gpu
    }

    fn step(&mut self, host: &mut Host, args: StepArgs<'_>) -> Result<(), Error> {
        let StepArgs {
            handles,
            config,
            effects,
        } = args;
        if let Some(e) = self.invalid.get() {
            return Err(e.clone());
        }
        if let Some(e) = self.unread.as_ref().and_then(Unread::error) {
            return Err(failed(e));
        }
        let handles = handles.handles();
        let asked = self.asked();
        let host_current = self.unread.as_ref().is_none_or(|u| u.motion_in_host);
        let gpu = self.gpu.get_mut().map_err(|_| poisoned())?;
        let uploaded_before = self.uploaded_last_step;
        self.uploaded_last_step = self.uploaded != handles;
        let changed = std::mem::take(&mut self.changed);
        if self.uploaded != handles {
            // Adding or removing a body brought the host arrays up to date first.
            debug_assert!(host_current, "bodies changed while the host was behind");
            gpu.set_bodies(&host.bodies, &host.states).map_err(failed)?;
            self.uploaded = handles.to_vec();
        } else {
            // With the host behind, the caller changed no pose or velocity since the last
            // step: every such change brings the host arrays up to date first.
            if host_current {
                for (i, (body, s)) in host.bodies.iter().zip(&host.states).enumerate() {
                    let (pose, synced) = &self.synced[i];
                    if body.pose != *pose {
                        gpu.set_pose(i, &body.pose).map_err(failed)?;
                    }
                    if s.linear_velocity != synced.linear_velocity
                        || s.angular_velocity != synced.angular_velocity
                    {
                        gpu.set_velocity(i, &s.linear_velocity, &s.angular_velocity)
                            .map_err(failed)?;
                    }
                }
            }
            // Groups, forces, torques and gravity scales need no motion from the GPU: they
            // are written whether or not the host has the last step's poses.
            for d in changed {
                gpu.set_body_properties(d, &host.bodies[d])
                    .map_err(failed)?;
            }
        }
        gpu.set_effects(*effects).map_err(failed)?;
        let mut reads = config.effects.readback.resolve(asked);
        reads.sleeping &= effects.sleep;
        gpu.request_reads(reads.request());
        gpu.step().map_err(failed)?;
        // What the step replaces, kept until its motion check passes.
        let previous = (
            self.unread.take(),
            std::mem::replace(&mut self.last_asked, asked),
            host.stats,
        );
        self.unread = Some(Unread::new(gpu.steps(), handles.to_vec(), reads));
        // The counts and times come from the step's results, read when asked for.
        host.stats = StepStats {
            bodies: host.bodies.len(),
            ..Default::default()
        };
        self.check_step(host, handles, previous, host_current, uploaded_before)
    }

    fn set_contact_events(&mut self, on: bool) -> Result<(), Error> {
        let gpu = self.gpu.get_mut().map_err(|_| poisoned())?;
        gpu.set_contact_events(on).map_err(failed)
    }

    fn touching_and_events(
        &self,
        host: &Host,
        previous: &[TouchingPair],
        sleep: bool,
    ) -> Result<TouchingAndEvents, Error> {
        let read = {
            let mut gpu = self.gpu.lock().map_err(|_| poisoned())?;
            gpu.read_contact_events().map_err(failed)?
        };
        let Some((list, compared)) = read else {
            return Ok((Vec::new(), None));
        };
        // Dense indices of the step, which the handles uploaded with it name.
        let handles = &self.uploaded;
        let name = |e: &GpuContactEvent| -> Option<(BodyHandle, BodyHandle)> {
            let (a, b) = (
                *handles.get(e.body_a as usize)?,
                *handles.get(e.body_b as usize)?,
            );
            Some(if a <= b { (a, b) } else { (b, a) })
        };
        let point = |e: &GpuContactEvent| Point3::new(e.point[0], e.point[1], e.point[2]);
        let mut touching: Vec<TouchingPair> = list
            .touching
            .iter()
            .filter_map(|e| {
                let (body_a, body_b) = name(e)?;
                Some(TouchingPair {
                    body_a,
                    body_b,
                    normal_impulse: e.point[3],
                    point: point(e),
                })
            })
            .collect();
        if sleep {
            // The GPU forms no pairs between bodies that sleep (or a sleeping body and a fixed
            // one), so a pair resting in an island that fell asleep is missing from its list
            // and its comparison would end it, and begin it again when the island wakes. As
            // on the CPU, whose sleeping islands keep their manifolds, such a pair still
            // touches: it is carried from the step before, with that step's impulse and point,
            // and the host compares the lists.
            touching.extend(self.kept_asleep(host, previous, &touching)?);
            touching.sort_unstable_by_key(|p| (p.body_a, p.body_b));
            return Ok((touching, None));
        }
        touching.sort_unstable_by_key(|p| (p.body_a, p.body_b));
        if !compared || self.uploaded_last_step {
            return Ok((touching, None));
        }
        let mut events: Vec<ContactEvent> = list
            .events
            .iter()
            .filter_map(|e| {
                let (body_a, body_b) = name(e)?;
                let kind = match e.kind {
                    EVENT_BEGIN => ContactEventKind::Begin,
                    EVENT_END => ContactEventKind::End,
                    _ => return None,
                };
                Some(ContactEvent {
                    kind,
                    body_a,
                    body_b,
                    normal_impulse: e.point[3],
                    point: point(e),
                })
            })
            .collect();
        events.sort_unstable_by_key(|e| (e.body_a, e.body_b));
        Ok((touching, Some(events)))
    }

    fn pose(&self, host: &Host, d: usize) -> Result<Pose, Error> {
        match self.unread_motion() {
            Some(u) => {
                let pose = u.poses(&self.gpu).map(|p| p[d]).map_err(failed)?;
                let moving = host.bodies[d].kind != BodyKind::Fixed;
                match bounds::check_motion(&pose, &Default::default(), &Default::default()) {
                    Some(e) if moving => Err(self.found(d, e)),
                    _ => Ok(pose),
                }
            }
            None => Ok(host.bodies[d].pose),
        }
    }

    fn state(&self, host: &Host, d: usize) -> Result<BodyState, Error> {
        match self.unread_motion() {
            Some(u) => {
                let v = u.velocities(&self.gpu).map(|v| v[d]).map_err(failed)?;
                let at_rest = Pose::identity();
                match bounds::check_motion(&at_rest, &v.linear_velocity, &v.angular_velocity) {
                    Some(e) => Err(self.found(d, e)),
                    None => Ok(v),
                }
            }
            None => Ok(host.states[d]),
        }
    }

    fn contacts<'a>(&'a self, host: &'a Host) -> ContactsView<'a> {
        match self.unread.as_ref().map(|u| u.contacts(&self.gpu)) {
            Some(Ok(ContactView {
                contacts, handles, ..
            })) => (contacts, handles),
            Some(Err(_)) => (&[], &[]),
            None => (&host.contacts, &host.contact_handles),
        }
    }

    fn stats<'a>(&'a self, host: &'a Host) -> &'a StepStats {
        match self.unread.as_ref() {
            Some(u) => u.stats(&self.gpu),
            None => &host.stats,
        }
    }

    fn is_sleeping(&self, host: &Host, d: usize, sleep: bool) -> Result<bool, Error> {
        match self.unread.as_ref() {
            Some(u) if sleep => u.sleeping(&self.gpu).map(|f| f[d]).map_err(failed),
            // Before any step, with sleep off, or once bodies were added or removed (which
            // wakes every body on the GPU), nothing sleeps: the host's awake state says so.
            _ => Ok(host.sleep.is_asleep(d)),
        }
    }

    fn sleeping_count(&self, host: &Host, sleep: bool) -> usize {
        match self.unread.as_ref() {
            Some(u) if sleep => u
                .sleeping(&self.gpu)
                .map_or(0, |f| f.iter().filter(|&&s| s).count()),
            _ => host.sleep.asleep_count(),
        }
    }

    fn wake(&mut self, host: &mut Host, d: usize) -> Result<(), Error> {
        // A body the GPU does not hold yet (added since the last step, or before the first)
        // arrives with the next step's upload, which starts every body awake.
        if d < self.uploaded.len() {
            let gpu = self.gpu.get_mut().map_err(|_| poisoned())?;
            gpu.wake_up(d).map_err(failed)?;
        }
        host.sleep.wake(d);
        Ok(())
    }

    fn sync_motion(&mut self, host: &mut Host) -> Result<(), Error> {
        if let Some(e) = self.invalid.get() {
            return Err(e.clone());
        }
        let Some(u) = self.unread.as_mut().filter(|u| !u.motion_in_host) else {
            return Ok(());
        };
        let poses = u.poses(&self.gpu).map_err(failed)?;
        let velocities = u.velocities(&self.gpu).map_err(failed)?;
        // State out of bounds never reaches the host arrays (nor, from them, the GPU again).
        if let Some(e) = check_results(host, &self.uploaded, poses, velocities) {
            let _ = self.invalid.set(e.clone());
            return Err(e);
        }
        for ((body, s), (pose, v)) in host
            .bodies
            .iter_mut()
            .zip(&mut host.states)
            .zip(poses.iter().zip(velocities))
        {
            body.pose = *pose;
            *s = *v;
        }
        self.synced = poses
            .iter()
            .copied()
            .zip(velocities.iter().copied())
            .collect();
        u.motion_in_host = true;
        Ok(())
    }

    fn sync_all(&mut self, host: &mut Host) -> Result<(), Error> {
        self.sync_motion(host)?;
        let Some(u) = self.unread.take() else {
            return Ok(());
        };
        let result = u.contacts(&self.gpu).map(|view| {
            host.contacts = view.contacts.clone();
            host.contact_handles = view.handles.clone();
            host.stats = *u.stats(&self.gpu);
        });
        self.last_asked = u.asked();
        if let Err(e) = result {
            self.unread = Some(u);
            return Err(failed(e));
        }
        Ok(())
    }

    fn body_changed(&mut self, host: &Host, d: usize) -> Result<(), Error> {
        let _ = host;
        if let Some(e) = self.invalid.get() {
            return Err(e.clone());
        }
        if !self.changed.contains(&d) {
            self.changed.push(d);
        }
        Ok(())
    }

    fn save(&self) -> Result<BackendSnapshot, Error> {
        if let Some(e) = self.invalid.get() {
            return Err(e.clone());
        }
        if let Some(e) = self.unread.as_ref().and_then(Unread::error) {
            return Err(failed(e));
        }
        // The GPU holds the last step's motion when the host is behind; else what the host
        // had when it was last brought up to date.
        let synced = match self.unread_motion() {
            Some(u) => {
                let poses = u.poses(&self.gpu).map_err(failed)?;
                let velocities = u.velocities(&self.gpu).map_err(failed)?;
                poses
                    .iter()
                    .copied()
                    .zip(velocities.iter().copied())
                    .collect()
            }
            None => self.synced.clone(),
        };
        let state = {
            let mut gpu = self.gpu.lock().map_err(|_| poisoned())?;
            gpu.save_state().map_err(failed)?
        };
        Ok(BackendSnapshot::Gpu {
            state: Box::new(state),
            uploaded: self.uploaded.clone(),
            synced,
            changed: self.changed.clone(),
        })
    }

    fn load(&mut self, saved: &BackendSnapshot, host: &Host) -> Result<(), Error> {
        let BackendSnapshot::Gpu {
            state,
            uploaded,
            synced,
            changed,
        } = saved
        else {
            return Err(wrong_backend(saved, self.kind()));
        };
        let n = host.bodies.len();
        if synced.len() != uploaded.len() || state.bodies.len() != uploaded.len() {
            return Err(corrupt_device(format!(
                "{} bodies on the GPU, {} handles, {} synced states",
                state.bodies.len(),
                uploaded.len(),
                synced.len()
            )));
        }
        if let Some(d) = changed.iter().find(|&&d| d >= n) {
            return Err(corrupt_device(format!("changed body {d} of {n}")));
        }
        let gpu = self.gpu.get_mut().map_err(|_| poisoned())?;
        gpu.load_state(state).map_err(corrupt_device)?;
        self.uploaded = uploaded.clone();
        self.synced = synced.clone();
        self.changed = changed.clone();
        self.unread = None;
        Ok(())
    }

    fn readback_bytes(&self) -> u64 {
        self.gpu.lock().map_or(0, |g| g.bytes_read())
    }

    fn device_buffer_bytes(&self) -> u64 {
        self.gpu.lock().map_or(0, |g| g.buffer_bytes())
    }

    fn device_buffer_sizes(&self) -> Vec<(&'static str, &'static str, u64)> {
        self.gpu.lock().map_or(Vec::new(), |g| g.buffer_sizes())
    }

    fn draw_buffers(&self) -> Option<(tumble_gpu::GpuContext, tumble_gpu::step::DrawBuffers)> {
        let gpu = self.gpu.lock().ok()?;
        Some((gpu.context().clone(), gpu.draw_buffers()?))
    }

    fn gpu_context(&self) -> Option<tumble_gpu::GpuContext> {
        Some(self.gpu.lock().ok()?.context().clone())
    }

    fn color_buffer(&self) -> Option<tumble_gpu::wgpu::Buffer> {
        let gpu = self.gpu.lock().ok()?;
        gpu.draw_buffers()?;
        Some(gpu.solver().colors().clone())
    }
}
