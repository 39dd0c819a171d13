//! The worlds of a `WorldBatch` on `Backend::Gpu`: every world of one config in one
//! [`GpuWorld`] (one set of buffers, one set of dispatches per step), each world's bodies one
//! run of its bodies (`GpuWorld::set_bodies_in_worlds`).
//!
//! A [`Group`] holds the device world of one config and where each world's bodies lie in it.
//! Each world of the group is a `World` whose backend is a [`Member`]: its `step` only stages
//! what the caller changed in that world (poses and velocities that differ from the device's,
//! changed properties) into the group's device world, and the batch then steps the group once
//! ([`Group::step`]). Reads follow `Backend::Gpu`'s rule: the host copy of a world is behind
//! after a step, and the first read or change after it fetches the group's poses and
//! velocities in one readback, shared by all its worlds, before serving or changing anything.
//!
//! A world's bodies move with the bits they have when the same world runs alone on
//! `Backend::Gpu` (tests/tests/batch/gpu.rs): the broad phase never pairs bodies of two worlds,
//! the coloring numbers each world's constraints from its first, and every other kernel works
//! per body or per pair. What a world alone has and a member has not: contacts, contact
//! events, statistics and sleep flags are not read back, and the device's own check of each
//! step's motion is off (the reads check every pose and velocity they fetch instead, and
//! name the body out of bounds). An upload that must grow the pair buffers, and a step whose
//! pairs overflow them, restart every world's contacts of the group once.

use std::sync::{Arc, Mutex, MutexGuard};

use tumble_geometry::Pose;
use tumble_gpu::step::{GpuWorld, GpuWorldConfig, ReadRequest, Snapshot};
use tumble_solver::{BodyState, Effects};

use super::gpu::check_results;
use super::{Host, StepArgs, StepBackend, shared_context, unavailable};
use crate::snapshot::BackendSnapshot;
use crate::{Backend, BodyHandle, Error, World, WorldConfig};

fn failed(e: impl std::fmt::Display) -> Error {
    unavailable(Backend::Gpu, e)
}

/// Where one world's bodies lie in the group's device world.
#[derive(Clone, Debug, Default)]
struct Placement {
    /// Which world (slots are reused; serials never are).
    serial: u64,
    /// The first body's index in the device world.
    first: usize,
    /// The world's handles in dense order, as uploaded.
    handles: Vec<BodyHandle>,
}

/// The state behind a group's lock.
#[derive(Debug)]
struct Inner {
    gpu: GpuWorld,
    /// Per batch slot, where that world's bodies lie as last uploaded (`None`: no world of
    /// this group there).
    placed: Vec<Option<Placement>>,
    /// Per batch slot, the serial of the group's world there now.
    members: Vec<Option<u64>>,
    /// Per batch slot, whether the world's host copy was brought up to date or a property
    /// changed since the last step: only those worlds have anything to stage (a world's
    /// every change brings its host copy up to date first).
    touched: Vec<bool>,
    /// The next world's serial.
    next_serial: u64,
    /// The layout must be uploaded again before the next step (a world or a body came or
    /// went).
    dirty: bool,
    /// Layouts uploaded so far: a member that saw an earlier one compares its host copy with
    /// the upload, not with what it synced before.
    layouts: u64,
    /// Steps of the device world; a member whose host copy is of an earlier step is behind.
    steps: u64,
    /// The last step's poses and velocities of every body, once read.
    read: Option<Arc<Snapshot>>,
    /// Worlds (by slot) whose pairs the next step drops: they were reset.
    forget: Vec<u32>,
    /// The effects the worlds need, merged: set when laid out, grown by each world's step
    /// that stages changes.
    effects: Option<Effects>,
}

/// One config's worlds in one device world.
#[derive(Debug)]
pub(crate) struct Group {
    config: WorldConfig,
    inner: Mutex<Inner>,
}

impl Group {
    /// An empty group for worlds of `config`. Errs when no GPU is available.
    pub(crate) fn new(config: &WorldConfig) -> Result<Arc<Self>, Error> {
        let ctx = shared_context().map_err(failed)?;
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
        .map_err(failed)?;
        Ok(Arc::new(Self {
            config: *config,
            inner: Mutex::new(Inner {
                gpu,
                placed: Vec::new(),
                members: Vec::new(),
                touched: Vec::new(),
                next_serial: 0,
                dirty: true,
                layouts: 0,
                steps: 0,
                read: None,
                forget: Vec::new(),
                effects: None,
            }),
        }))
    }

    /// The config every world of the group has.
    pub(crate) fn config(&self) -> &WorldConfig {
        &self.config
    }

    fn lock(&self) -> Result<MutexGuard<'_, Inner>, Error> {
        self.inner
            .lock()
            .map_err(|_| failed("the GPU batch's lock was poisoned by a panic"))
    }

    /// A world for batch slot `slot` of this group's config, with no bodies yet.
    pub(crate) fn world(self: &Arc<Self>, slot: u32) -> Result<World, Error> {
        let mut inner = self.lock()?;
        let s = slot as usize;
        if inner.members.len() <= s {
            inner.members.resize(s + 1, None);
        }
        let serial = inner.next_serial;
        inner.next_serial += 1;
        inner.members[s] = Some(serial);
        inner.dirty = true;
        let member = Member {
            group: self.clone(),
            slot,
            serial,
            synced: Vec::new(),
            host_step: inner.steps,
            layout: u64::MAX,
            changed: Vec::new(),
        };
        World::with_backend(self.config, Box::new(member))
    }

    /// Slot `slot`'s world left the batch.
    pub(crate) fn remove(&self, slot: u32) -> Result<(), Error> {
        let mut inner = self.lock()?;
        if let Some(m) = inner.members.get_mut(slot as usize) {
            *m = None;
        }
        inner.dirty = true;
        Ok(())
    }

    /// A body came or went in one of the group's worlds: the next step uploads every world.
    pub(crate) fn reshaped(&self) -> Result<(), Error> {
        self.lock()?.dirty = true;
        Ok(())
    }

    /// The world in slot `slot` was reset: the next step drops its pairs of the last step.
    pub(crate) fn forget(&self, slot: u32) -> Result<(), Error> {
        let mut inner = self.lock()?;
        if !inner.forget.contains(&slot) {
            inner.forget.push(slot);
        }
        Ok(())
    }

    /// Per batch slot, whether the world has changes to stage in the next step (see
    /// `Inner::touched`); cleared for the step after.
    pub(crate) fn take_touched(&self) -> Result<Vec<bool>, Error> {
        let mut inner = self.lock()?;
        let n = inner.members.len();
        Ok(std::mem::replace(&mut inner.touched, vec![false; n]))
    }

    /// Whether the next step must upload every world again.
    pub(crate) fn is_dirty(&self) -> Result<bool, Error> {
        Ok(self.lock()?.dirty)
    }

    /// Whether any world of the group lives in the batch.
    pub(crate) fn is_empty(&self) -> Result<bool, Error> {
        Ok(self.lock()?.members.iter().all(Option::is_none))
    }

    /// Uploads every world again when the layout changed: `worlds` are the group's worlds by
    /// slot, in slot order, each with its host copy brought up to date by the caller. The
    /// worlds whose bodies are the ones uploaded last time keep their contact history
    /// (`GpuWorld::set_bodies_in_worlds_keeping`); the others start as new, as a world alone
    /// does after a body is added or removed.
    pub(crate) fn lay_out(&self, worlds: &mut [(u32, &mut World)]) -> Result<(), Error> {
        let mut inner = self.lock()?;
        let inner = &mut *inner;
        if !inner.dirty {
            return Ok(());
        }
        let total: usize = worlds.iter().map(|(_, w)| w.host.bodies.len()).sum();
        let mut bodies = Vec::with_capacity(total);
        let mut states = Vec::with_capacity(total);
        let mut index = Vec::with_capacity(total);
        let mut placed: Vec<Option<Placement>> = vec![None; inner.members.len()];
        let mut w = 0u32;
        for (slot, world) in worlds.iter() {
            let serial = inner.members[*slot as usize]
                .ok_or_else(|| failed("a batch world is missing from its group"))?;
            placed[*slot as usize] = Some(Placement {
                serial,
                first: bodies.len(),
                handles: world.handles.handles().to_vec(),
            });
            if world.host.bodies.is_empty() {
                continue;
            }
            bodies.extend_from_slice(&world.host.bodies);
            states.extend_from_slice(&world.host.states);
            index.extend(std::iter::repeat_n(w, world.host.bodies.len()));
            w += 1;
        }
        inner.effects = worlds.iter().map(|(_, w)| w.effects()).reduce(merge);
        let remap = remap(&inner.placed, &placed, &inner.forget, bodies.len());
        // The device keeps the last upload's bodies until the next: the remap is of those (an
        // upload of no bodies at all leaves none to remap from).
        if inner.gpu.body_count() > 0 && remap.len() == inner.gpu.body_count() {
            inner
                .gpu
                .set_bodies_in_worlds_keeping(&bodies, &states, &index, &remap)
                .map_err(failed)?;
        } else {
            inner
                .gpu
                .set_bodies_in_worlds(&bodies, &states, &index)
                .map_err(failed)?;
        }
        inner.placed = placed;
        inner.dirty = false;
        inner.layouts += 1;
        // Every world compares its host copy with the upload at its next step.
        inner.touched = vec![true; inner.members.len()];
        inner.forget.clear();
        inner.read = None;
        Ok(())
    }

    /// The step of every world of the group, once each world's `World::step` staged its
    /// changes. Nothing is waited for.
    pub(crate) fn step(&self) -> Result<(), Error> {
        let mut inner = self.lock()?;
        let inner = &mut *inner;
        if inner.placed.iter().flatten().all(|p| p.handles.is_empty()) {
            // No body in any world: the worlds' steps only counted.
            inner.steps += 1;
            return Ok(());
        }
        if !inner.forget.is_empty() {
            let worlds = device_worlds(&inner.placed, &inner.forget);
            inner.gpu.forget_worlds(&worlds).map_err(failed)?;
            inner.forget.clear();
        }
        if let Some(effects) = inner.effects {
            inner.gpu.set_effects(effects).map_err(failed)?;
        }
        inner.gpu.step().map_err(failed)?;
        inner.steps += 1;
        inner.read = None;
        Ok(())
    }

    /// GPU seconds per stage of the last step (empty without timestamps). Blocks.
    pub(crate) fn timings(&self) -> Result<Vec<(&'static str, f64)>, Error> {
        self.lock()?.gpu.timings().map_err(failed)
    }

    /// Bytes of device buffers the group holds.
    pub(crate) fn device_buffer_bytes(&self) -> u64 {
        self.lock().map_or(0, |i| i.gpu.buffer_bytes())
    }
}

/// The renumbering of the last upload's bodies for the next (`remap_pairs.wgsl`): a world of
/// the same serial and handles that was not reset keeps its pairs, moved to its new first
/// body; any other world's pairs drop to the new first body of the first world from its slot
/// on (or past the last body).
fn remap(
    old: &[Option<Placement>],
    new: &[Option<Placement>],
    reset: &[u32],
    new_total: usize,
) -> Vec<u32> {
    use tumble_gpu::kernels::remap_pairs::REMAP_DROPPED;
    let mut out = Vec::new();
    for (slot, p) in old.iter().enumerate() {
        let Some(p) = p else { continue };
        let kept = new.get(slot).and_then(Option::as_ref).filter(|n| {
            n.serial == p.serial && n.handles == p.handles && !reset.contains(&(slot as u32))
        });
        match kept {
            Some(n) => out.extend((0..p.handles.len()).map(|i| (n.first + i) as u32)),
            None => {
                let drop_to = new[slot.min(new.len())..]
                    .iter()
                    .flatten()
                    .find(|n| !n.handles.is_empty())
                    .map_or(new_total, |n| n.first);
                out.extend(std::iter::repeat_n(
                    REMAP_DROPPED | drop_to as u32,
                    p.handles.len(),
                ));
            }
        }
    }
    out
}

/// The device world indices of the worlds in `slots`: worlds with bodies count, in slot order.
fn device_worlds(placed: &[Option<Placement>], slots: &[u32]) -> Vec<u32> {
    let mut index = 0u32;
    let mut out = Vec::new();
    for (slot, p) in placed.iter().enumerate() {
        let Some(p) = p else { continue };
        if p.handles.is_empty() {
            continue;
        }
        if slots.contains(&(slot as u32)) {
            out.push(index);
        }
        index += 1;
    }
    out
}

impl Inner {
    /// Marks slot `slot`'s world as having changes to stage.
    fn touch(&mut self, slot: u32) {
        let s = slot as usize;
        if self.touched.len() <= s {
            self.touched.resize(s + 1, false);
        }
        self.touched[s] = true;
    }

    /// The last step's poses and velocities, read once.
    fn snapshot(&mut self) -> Result<Arc<Snapshot>, Error> {
        if let Some(read) = &self.read {
            return Ok(read.clone());
        }
        let read = Arc::new(self.gpu.read_now(ReadRequest::MOTION).map_err(failed)?);
        self.read = Some(read.clone());
        Ok(read)
    }
}

/// `World`'s backend for a world of a GPU batch.
#[derive(Debug)]
struct Member {
    group: Arc<Group>,
    /// The world's batch slot.
    slot: u32,
    /// The world's serial in its group.
    serial: u64,
    /// Pose and velocities of each body as the device had them when the host copy was last
    /// brought up to date (what the next step compares the host copy with).
    synced: Vec<(Pose, BodyState)>,
    /// The device step the host copy is of.
    host_step: u64,
    /// The layout `synced` belongs to.
    layout: u64,
    /// Dense indices whose properties changed since the last step.
    changed: Vec<usize>,
}

impl Member {
    /// The world's placement and the group, locked.
    fn placed<'a>(&self, inner: &'a Inner) -> Result<&'a Placement, Error> {
        inner
            .placed
            .get(self.slot as usize)
            .and_then(Option::as_ref)
            .filter(|p| p.serial == self.serial)
            .ok_or_else(|| failed("the world is not laid out in its batch's device world"))
    }

    /// Whether the host copy is of an earlier step than the device world's (whose layout,
    /// until the next upload, is the one that step ran with).
    fn behind(&self, inner: &Inner) -> bool {
        self.host_step != inner.steps
    }

    /// Body `d`'s pose and velocities after the last step, from the group's readback; an
    /// error naming the body when they are out of bounds (as `Backend::Gpu`'s reads).
    fn read(&self, host: &Host, d: usize) -> Result<(Pose, BodyState), Error> {
        let mut inner = self.group.lock()?;
        let placed = self.placed(&inner)?;
        let (first, handle) = (placed.first, placed.handles.get(d).copied());
        let snap = inner.snapshot()?;
        let (pose, state) = (snap.pose(first + d), snap.state(first + d));
        if let Some(h) = handle {
            checked(host, &[h], d, &pose, &state)?;
        }
        Ok((pose, state))
    }
}

impl StepBackend for Member {
    fn kind(&self) -> Backend {
        Backend::Gpu
    }

    fn step(&mut self, host: &mut Host, args: StepArgs<'_>) -> Result<(), Error> {
        let mut inner = self.group.lock()?;
        let inner = &mut *inner;
        inner.effects = Some(match inner.effects {
            None => *args.effects,
            Some(e) => merge(e, *args.effects),
        });
        if inner.dirty {
            // Laid out again before the group's step (the batch does it first); a world
            // whose bodies changed and was not is an error of the batch's, never silent.
            return Err(failed(
                "a batch world's bodies changed without a new layout",
            ));
        }
        let placed = self.placed(inner)?;
        if placed.handles.as_slice() != args.handles.handles() {
            return Err(failed(
                "a batch world's bodies changed without a new layout",
            ));
        }
        let first = placed.first;
        if self.host_step != inner.steps {
            // The host copy is behind: nothing was changed since the last step (every change
            // brings it up to date first).
            self.changed.clear();
            return Ok(());
        }
        if self.layout != inner.layouts {
            // Laid out since the last sync: the device has the host copy.
            self.layout = inner.layouts;
            self.synced = host
                .bodies
                .iter()
                .zip(&host.states)
                .map(|(b, s)| (b.pose, *s))
                .collect();
        }
        let gpu = &mut inner.gpu;
        for (d, (body, s)) in host.bodies.iter().zip(&host.states).enumerate() {
            // Compared bit for bit: a reset that writes +0 over a -0 must reach the device.
            let (pose, synced) = &self.synced[d];
            if pose_bits(&body.pose) != pose_bits(pose) {
                gpu.set_pose(first + d, &body.pose).map_err(failed)?;
            }
            if velocity_bits(s) != velocity_bits(synced) {
                gpu.set_velocity(first + d, &s.linear_velocity, &s.angular_velocity)
                    .map_err(failed)?;
            }
        }
        for d in std::mem::take(&mut self.changed) {
            gpu.set_body_properties(first + d, &host.bodies[d])
                .map_err(failed)?;
        }
        Ok(())
    }

    fn pose(&self, host: &Host, d: usize) -> Result<Pose, Error> {
        if !self.behind(&*self.group.lock()?) {
            return Ok(host.bodies[d].pose);
        }
        Ok(self.read(host, d)?.0)
    }

    fn state(&self, host: &Host, d: usize) -> Result<BodyState, Error> {
        if !self.behind(&*self.group.lock()?) {
            return Ok(host.states[d]);
        }
        Ok(self.read(host, d)?.1)
    }

    fn fetched_motion(&self, host: &Host) -> Result<Option<(Arc<Snapshot>, usize)>, Error> {
        let mut inner = self.group.lock()?;
        if !self.behind(&inner) {
            return Ok(None);
        }
        let placed = self.placed(&inner)?;
        let (first, handles) = (placed.first, placed.handles.clone());
        let snap = inner.snapshot()?;
        // Every body of the world is checked before any is read out.
        for d in 0..handles.len() {
            checked(
                host,
                &handles,
                d,
                &snap.pose(first + d),
                &snap.state(first + d),
            )?;
        }
        Ok(Some((snap, first)))
    }

    fn sync_motion(&mut self, host: &mut Host) -> Result<(), Error> {
        let mut inner = self.group.lock()?;
        if !self.behind(&inner) {
            return Ok(());
        }
        let placed = self.placed(&inner)?;
        let (first, handles) = (placed.first, placed.handles.clone());
        let snap = inner.snapshot()?;
        let n = host.bodies.len();
        let poses: Vec<Pose> = (0..n).map(|d| snap.pose(first + d)).collect();
        let states: Vec<BodyState> = (0..n).map(|d| snap.state(first + d)).collect();
        // State out of bounds never reaches the host copy (nor, from it, the device again).
        if let Some(e) = check_results(host, &handles, &poses, &states) {
            return Err(e);
        }
        for ((body, s), (pose, v)) in host
            .bodies
            .iter_mut()
            .zip(&mut host.states)
            .zip(poses.iter().zip(&states))
        {
            body.pose = *pose;
            *s = *v;
        }
        self.synced = poses.into_iter().zip(states).collect();
        self.host_step = inner.steps;
        self.layout = inner.layouts;
        inner.touch(self.slot);
        Ok(())
    }

    fn sync_all(&mut self, host: &mut Host) -> Result<(), Error> {
        self.sync_motion(host)
    }

    fn body_changed(&mut self, host: &Host, d: usize) -> Result<(), Error> {
        let _ = host;
        if !self.changed.contains(&d) {
            self.changed.push(d);
        }
        self.group.lock()?.touch(self.slot);
        Ok(())
    }

    fn wake(&mut self, host: &mut Host, d: usize) -> Result<(), Error> {
        let _ = host;
        let mut inner = self.group.lock()?;
        if inner.dirty {
            return Ok(());
        }
        let first = self.placed(&inner)?.first;
        inner.gpu.wake_up(first + d).map_err(failed)
    }

    fn save(&self) -> Result<BackendSnapshot, Error> {
        Err(failed(
            "a world of a GPU batch has no snapshot of its own (WorldBatch::save_state keeps its state)",
        ))
    }

    fn load(&mut self, saved: &BackendSnapshot, host: &Host) -> Result<(), Error> {
        let _ = (saved, host);
        Err(failed(
            "a world of a GPU batch has no snapshot of its own (WorldBatch::reset returns to its saved state)",
        ))
    }
}

/// Effects the step runs for two sets of worlds together: each effect any of them needs.
fn merge(a: Effects, b: Effects) -> Effects {
    Effects {
        gravity: a.gravity || b.gravity,
        friction: a.friction || b.friction,
        restitution: a.restitution || b.restitution,
        rotation: a.rotation || b.rotation,
        kinematic: a.kinematic || b.kinematic,
        sleep: a.sleep || b.sleep,
    }
}

/// An error naming body `d` (of `handles`) when its pose or velocities are out of bounds:
/// `check_results` for one body.
fn checked(
    host: &Host,
    handles: &[BodyHandle],
    d: usize,
    pose: &Pose,
    state: &BodyState,
) -> Result<(), Error> {
    let (Some(body), Some(handle)) = (host.bodies.get(d), handles.get(d..d + 1)) else {
        return Ok(());
    };
    let mut one = Host::default();
    one.bodies.push(*body);
    match check_results(&one, handle, &[*pose], &[*state]) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

fn pose_bits(p: &Pose) -> [u32; 7] {
    let (t, q) = (p.translation.vector, p.rotation.coords);
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w].map(f32::to_bits)
}

fn velocity_bits(s: &BodyState) -> [u32; 6] {
    let (v, w) = (s.linear_velocity, s.angular_velocity);
    [v.x, v.y, v.z, w.x, w.y, w.z].map(f32::to_bits)
}
