//! [`GpuWorld`]'s motion check: a step that leaves a body with a non-finite pose or velocity
//! (or its centre beyond `MAX_POSITION`) is found and undone.
//!
//! With the check on ([`GpuWorld::set_motion_check`]), each recorded step begins with a copy
//! of the state buffers of the stages' pools into a shadow pool on the device (a checkpoint:
//! device-to-device copies, no host traffic; each pool's per-step scratch, which every step
//! rewrites before reading, is left out: [`crate::buffer_pool::BufferPool::with_per_step`]),
//! and ends with `check_motion`, which flags the
//! first body out of bounds in a 4-byte buffer copied back with the step.
//! [`GpuWorld::motion_flag`] waits for that copy; only when it is set does the host read the
//! state ([`GpuWorld::read_now`]) and call [`GpuWorld::roll_back`], which copies the
//! checkpoint back and puts the host-side counters (step count, parities, lagged statistics,
//! idle tracker, queued wakes and impulses) as they were, so the next step computes what the
//! bad one would have computed from the same state.

use super::*;
use crate::kernel::Kernel;
use crate::kernels::check_motion::{CHECK_MOTION, flagged_body};
use crate::step::idle::IdleSteps;

/// The host-side state a checked step changes, as it was before the step.
#[derive(Debug)]
pub(super) struct Before {
    steps: u64,
    known_manifolds: Option<u32>,
    pair_overflows: u32,
    last_path: Option<SolvePath>,
    idle: IdleSteps,
    source: ContactSource,
    host_count: u32,
    collision: (u64, u64),
    solver_parity: usize,
    queued_wakes: Vec<u32>,
    impulses: Vec<GpuImpulse>,
}

/// The check's kernel, buffers and the checkpoint of the step in flight.
#[derive(Debug)]
pub(super) struct MotionCheck {
    kernel: Kernel,
    /// One `u32` the kernel flags.
    flag: wgpu::Buffer,
    /// Its copy for the host.
    staging: wgpu::Buffer,
    /// Shadow pools: world, collision, solver, sleep.
    shadow: [BufferPool; 4],
    /// The state before the last step, while that step was recorded with the check.
    before: Option<Before>,
    /// Whether the last step's flag was copied and not yet read.
    armed: bool,
}

impl MotionCheck {
    pub(super) fn new(ctx: &GpuContext) -> Result<Self, GpuError> {
        let buffer = |label, usage| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 4,
                usage,
                mapped_at_creation: false,
            })
        };
        Ok(Self {
            kernel: Kernel::new(ctx, &CHECK_MOTION)?,
            flag: buffer("motion check flag", STORAGE_USAGE),
            staging: buffer(
                "motion check staging",
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            shadow: std::array::from_fn(|_| BufferPool::new(ctx)),
            before: None,
            armed: false,
        })
    }
}

impl GpuWorld {
    /// Turns the motion check on or off from the next step on (off by default; the facade's
    /// `Backend::Gpu` turns it on). On, each step costs a device copy of the state buffers,
    /// one dispatch and a 4-byte readback, and the shadow copies double the state buffers'
    /// memory.
    pub fn set_motion_check(&mut self, on: bool) -> Result<(), GpuError> {
        match (on, self.check.is_some()) {
            (true, false) => self.check = Some(MotionCheck::new(&self.ctx)?),
            (false, true) => self.check = None,
            _ => {}
        }
        Ok(())
    }

    /// The check's shadow copies by pool (world, collision, solver, sleep) and buffer name,
    /// with their sizes in bytes; empty while the check is off.
    pub(super) fn shadow_sizes(&self) -> Vec<(&'static str, &'static str, u64)> {
        let Some(check) = &self.check else {
            return Vec::new();
        };
        let pools = [
            "check world",
            "check collision",
            "check solver",
            "check sleep",
        ];
        pools
            .into_iter()
            .zip(&check.shadow)
            .flat_map(|(pool, shadow)| shadow.sizes().into_iter().map(move |(n, b)| (pool, n, b)))
            .collect()
    }

    /// The host-side state before a step (while the check is on).
    pub(super) fn before_step(&self) -> Option<Before> {
        self.check.as_ref()?;
        Some(Before {
            steps: self.steps,
            known_manifolds: self.known_manifolds,
            pair_overflows: self.pair_overflows,
            last_path: self.last_path,
            idle: self.idle,
            source: self.source,
            host_count: self.host_count,
            collision: self.collision.step_state(),
            solver_parity: self.solver.parity(),
            queued_wakes: self.sleep.queued().to_vec(),
            impulses: self.impulses.clone(),
        })
    }

    /// Records the checkpoint at the start of a step's commands and keeps `before` for
    /// [`Self::roll_back`]; a no-op with the check off.
    pub(super) fn record_checkpoint(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        before: Option<Before>,
    ) {
        let Some(check) = &mut self.check else {
            return;
        };
        let [world, collision, solver, sleep] = &mut check.shadow;
        self.pool.record_checkpoint(encoder, world);
        self.collision.record_checkpoint(encoder, collision);
        self.solver.pool().record_checkpoint(encoder, solver);
        self.sleep.record_checkpoint(encoder, sleep);
        encoder.clear_buffer(&check.flag, 0, None);
        check.before = before;
    }

    /// Records `check_motion` and the flag's copy at the end of a step (with the check on and
    /// a checkpoint recorded for the step).
    pub(super) fn record_motion_check(&mut self, encoder: &mut wgpu::CommandEncoder) {
        let Some(check) = &mut self.check else {
            return;
        };
        if check.before.is_none() || self.bodies.is_empty() {
            return;
        }
        let buffers = self.collision.buffers(self.pool.get(BODIES));
        let work = self.collision.body_work();
        let group = check.kernel.bind_named(&self.ctx, |name| match name {
            "body_work" => work,
            "poses" => buffers.poses,
            "velocities" => buffers.velocities,
            "flag" => &check.flag,
            _ => unreachable!("no check_motion binding {name}"),
        });
        {
            let mut pass = self.timer.begin_pass(encoder, "check_motion");
            check
                .kernel
                .dispatch(&mut pass, &group, self.bodies.len() as u32);
        }
        encoder.copy_buffer_to_buffer(&check.flag, 0, &check.staging, 0, 4);
        check.armed = true;
    }

    /// The first body the last step's check flagged, waiting for the step; `None` when none
    /// was, or when the step was not checked (check off, an idle step's repeat, no bodies).
    pub fn motion_flag(&mut self) -> Result<Option<u32>, GpuError> {
        let Some(check) = &mut self.check else {
            return Ok(None);
        };
        if !std::mem::take(&mut check.armed) {
            return Ok(None);
        }
        // An empty submission after the step's: waiting for it waits for the step and not for
        // work other worlds on the shared device submit meanwhile.
        let index = self.ctx.submit(self.ctx.encoder("motion check"))?;
        let done = std::sync::Arc::new(std::sync::Mutex::new(None));
        let sink = done.clone();
        check.staging.map_async(wgpu::MapMode::Read, .., move |r| {
            *sink.lock().expect("flag map lock") = Some(r.map_err(|e| e.to_string()));
        });
        let waited = self.ctx.wait_until(Some(index), || {
            done.lock().expect("flag map lock").is_some()
        });
        let status = done.lock().expect("flag map lock").take();
        if let Err(e) = waited {
            if status.is_some() {
                check.staging.unmap();
            }
            return Err(e);
        }
        status
            .expect("the map callback has run")
            .map_err(GpuError::Device)?;
        let flag = {
            let view = check
                .staging
                .get_mapped_range(..)
                .map_err(|e| GpuError::Device(e.to_string()))?;
            u32::from_le_bytes([view[0], view[1], view[2], view[3]])
        };
        check.staging.unmap();
        Ok(flagged_body(flag))
    }

    /// Undoes the last step, which was recorded with the motion check: the checkpoint is
    /// copied back on the device and the host-side state is put back as it was before the
    /// step. Errs, changing nothing, when there is no checkpoint of the last step.
    pub fn roll_back(&mut self) -> Result<(), GpuError> {
        let check = self
            .check
            .as_mut()
            .ok_or_else(|| no_checkpoint("the check is off"))?;
        // A checkpoint of an earlier step (the last one skipped as idle, or ran on host
        // manifolds) is no checkpoint of the last step.
        let before = check
            .before
            .take_if(|b| b.steps + 1 == self.steps)
            .ok_or_else(|| no_checkpoint("the last step recorded none"))?;
        check.armed = false;
        let [world, collision, solver, sleep] = &check.shadow;
        let mut encoder = self.ctx.encoder("roll back");
        self.pool.copy_back(&mut encoder, world);
        self.collision.copy_back(&mut encoder, collision);
        self.solver.pool().copy_back(&mut encoder, solver);
        self.sleep.copy_back(&mut encoder, sleep);
        self.ctx.submit(encoder)?;
        // The rolled-back step's read, if it recorded one, is taken and dropped.
        if self.pending.back().is_some_and(|p| p.step == self.steps) {
            let last = self.pending.pop_back().expect("checked above");
            self.readback.wait(&last.ticket, &last.regions)?;
        }
        self.stats.undo_last()?;
        self.steps = before.steps;
        self.known_manifolds = before.known_manifolds;
        self.pair_overflows = before.pair_overflows;
        self.last_path = before.last_path;
        self.idle = before.idle;
        self.source = before.source;
        self.host_count = before.host_count;
        self.collision.set_step_state(before.collision);
        self.solver.set_parity(before.solver_parity);
        self.sleep.set_queued(before.queued_wakes);
        self.impulses = before.impulses;
        if let Some(events) = &mut self.events {
            events.forget();
        }
        Ok(())
    }
}

fn no_checkpoint(why: &str) -> GpuError {
    GpuError::InvalidInput {
        field: "roll_back".into(),
        value: format!("no checkpoint: {why}"),
    }
}
