//! The worlds of a `WorldBatch` on `Backend::Gpu`: every world of one config in one
//! [`GpuWorld`] (one set of buffers, one set of dispatches per step), each world's bodies one
//! run of its bodies (`GpuWorld::set_bodies_in_worlds`).
//!
//! A [`Group`] (`super::group`) holds the device world of one config and where each world's bodies lie in it.
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

use std::sync::Arc;

use tumble_geometry::Pose;
use tumble_gpu::step::Snapshot;
use tumble_solver::BodyState;

use super::gpu::check_results;
use super::group::{Group, Inner, Placement, failed, merge};
use super::{Host, StepArgs, StepBackend};
use crate::snapshot::BackendSnapshot;
use crate::{Backend, BodyHandle, Error};

/// `World`'s backend for a world of a GPU batch.
#[derive(Debug)]
pub(super) struct Member {
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
    /// The backend of the world in batch slot `slot` of `group`, the group's `serial`-th,
    /// created when the group had taken `steps` steps.
    pub(super) fn new(group: Arc<Group>, slot: u32, serial: u64, steps: u64) -> Self {
        Self {
            group,
            slot,
            serial,
            synced: Vec::new(),
            host_step: steps,
            layout: u64::MAX,
            changed: Vec::new(),
        }
    }

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
