//! A GPU batch's device world of one config ([`Group`]): every world of that config in one
//! [`GpuWorld`], each world's bodies one run, where each lies, the layout uploaded again when
//! worlds or bodies come and go (keeping the unchanged worlds' contacts), and the one step of
//! them all. Its worlds' backend is [`super::member::Member`].

use std::sync::{Arc, Mutex, MutexGuard};

use tumble_gpu::step::{GpuWorld, ReadRequest, Snapshot};
use tumble_solver::Effects;

use super::gpu::gpu_world_config;
use super::member::Member;
use super::{shared_context, unavailable};
use crate::{Backend, BodyHandle, Error, World, WorldConfig};

pub(super) fn failed(e: impl std::fmt::Display) -> Error {
    unavailable(Backend::Gpu, e)
}

/// Where one world's bodies lie in the group's device world.
#[derive(Clone, Debug, Default)]
pub(super) struct Placement {
    /// Which world (slots are reused; serials never are).
    pub(super) serial: u64,
    /// The first body's index in the device world.
    pub(super) first: usize,
    /// The world's handles in dense order, as uploaded.
    pub(super) handles: Vec<BodyHandle>,
}

/// The state behind a group's lock.
#[derive(Debug)]
pub(super) struct Inner {
    pub(super) gpu: GpuWorld,
    /// Per batch slot, where that world's bodies lie as last uploaded (`None`: no world of
    /// this group there).
    pub(super) placed: Vec<Option<Placement>>,
    /// Per batch slot, the serial of the group's world there now.
    pub(super) members: Vec<Option<u64>>,
    /// Per batch slot, whether the world's host copy was brought up to date or a property
    /// changed since the last step: only those worlds have anything to stage (a world's
    /// every change brings its host copy up to date first).
    pub(super) touched: Vec<bool>,
    /// The next world's serial.
    pub(super) next_serial: u64,
    /// The layout must be uploaded again before the next step (a world or a body came or
    /// went).
    pub(super) dirty: bool,
    /// Layouts uploaded so far: a member that saw an earlier one compares its host copy with
    /// the upload, not with what it synced before.
    pub(super) layouts: u64,
    /// Steps of the device world; a member whose host copy is of an earlier step is behind.
    pub(super) steps: u64,
    /// The last step's poses and velocities of every body, once read.
    pub(super) read: Option<Arc<Snapshot>>,
    /// Worlds (by slot) whose pairs the next step drops: they were reset.
    pub(super) forget: Vec<u32>,
    /// The effects the worlds need, merged: set when laid out, grown by each world's step
    /// that stages changes.
    pub(super) effects: Option<Effects>,
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
        let gpu = GpuWorld::new(&ctx, gpu_world_config(config, &ctx)).map_err(failed)?;
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

    pub(super) fn lock(&self) -> Result<MutexGuard<'_, Inner>, Error> {
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
        let member = Member::new(self.clone(), slot, serial, inner.steps);
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
    pub(super) fn touch(&mut self, slot: u32) {
        let s = slot as usize;
        if self.touched.len() <= s {
            self.touched.resize(s + 1, false);
        }
        self.touched[s] = true;
    }

    /// The last step's poses and velocities, read once.
    pub(super) fn snapshot(&mut self) -> Result<Arc<Snapshot>, Error> {
        if let Some(read) = &self.read {
            return Ok(read.clone());
        }
        let read = Arc::new(self.gpu.read_now(ReadRequest::MOTION).map_err(failed)?);
        self.read = Some(read.clone());
        Ok(read)
    }
}

/// Effects the step runs for two sets of worlds together: each effect any of them needs.
pub(super) fn merge(a: Effects, b: Effects) -> Effects {
    Effects {
        gravity: a.gravity || b.gravity,
        friction: a.friction || b.friction,
        restitution: a.restitution || b.restitution,
        rotation: a.rotation || b.rotation,
        kinematic: a.kinematic || b.kinematic,
        sleep: a.sleep || b.sleep,
    }
}
