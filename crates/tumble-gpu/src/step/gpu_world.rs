//! [`GpuWorld`]: the whole step on the GPU. Bodies are uploaded once; each step records
//! `update_aabbs -> broad_phase -> narrow_phase (with matching) -> color -> prepare ->
//! substeps -> finish` into ONE command encoder, submits it once, and reads nothing back
//! unless asked (asynchronously, double-buffered).

use std::collections::VecDeque;

use tumble_geometry::{Point3, Pose, Vec3};
use tumble_solver::{Body, BodyState};

use crate::buffer_pool::{BufferPool, STORAGE_USAGE};
use crate::collision::GpuCollision;
use crate::layout::{GpuContact, GpuManifold, GpuPose, GpuVelocity, WorkList};
use crate::readback::{Readback, Region};
use crate::sleep::constants::AWAKE;
use crate::sleep::{GpuSleep, SleepInputs};
use crate::solver::apply_impulses::ApplyImpulsesArgs;
use crate::solver::convert::{gpu_body, gpu_manifold, gpu_pose, gpu_shape, gpu_tilt, gpu_velocity};
use crate::solver::layout::{GpuBody, GpuImpulse, GpuTilt};
use crate::solver::{Effects, GpuSolver, SolvePath, SolverInputs, StepParams};
use crate::{GpuContext, GpuError, MAX_MANIFOLD_POINTS, StageTimer};

use super::config::{GpuWorldConfig, PathPolicy};
use super::idle::IdleSteps;
use super::read_plan::{PendingRead, ReadSizes, decode};
use super::snapshot::{ContactSnapshot, ReadRequest, Snapshot};
use super::stats_ring::StatsRing;

mod host_contacts;

const BODIES: &str = "world bodies";
const HOST_MANIFOLDS: &str = "host manifolds";
const HOST_POINTS: &str = "host contact points";
const HOST_WORK: &str = "host manifold work list";

/// Manifolds per body assumed before any step has reported its count: a cube in a pile has
/// 6.6 to 7.2 manifolds, speculative ones included (pyramids of 4 to 20 layers).
pub const ESTIMATED_PAIRS_PER_BODY: u32 = 7;

/// Manifolds copied by an asynchronous contact readback beyond the last known count, as a
/// fraction and a floor: a step with more is read back truncated (see
/// [`ContactSnapshot::work`]) and [`GpuWorld::read_now`] gives the exact list.
const READ_HEADROOM: f32 = 0.25;
const READ_MIN_MANIFOLDS: u32 = 1024;

/// Longest wait for a readback before reporting a device error: far beyond any step (a lost
/// device, not a slow one).
const READ_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(60);

/// Where the manifolds of the last step came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ContactSource {
    /// The GPU collision stages (the buffers of the step's parity).
    Collision,
    /// Manifolds uploaded by the host ([`GpuWorld::step_with_contacts`]).
    Host,
}

/// A world of boxes simulated entirely on the GPU.
#[derive(Debug)]
pub struct GpuWorld {
    ctx: GpuContext,
    config: GpuWorldConfig,
    collision: GpuCollision,
    solver: GpuSolver,
    pool: BufferPool,
    bodies: Vec<Body>,
    impulses: Vec<GpuImpulse>,
    stats: StatsRing,
    known_manifolds: Option<u32>,
    pair_overflows: u32,
    readback: Readback,
    request: ReadRequest,
    pending: VecDeque<PendingRead>,
    timer: StageTimer,
    steps: u64,
    source: ContactSource,
    host_count: u32,
    last_path: Option<SolvePath>,
    /// Bytes copied from the GPU for the host so far.
    bytes_read: u64,
    sleep: GpuSleep,
    idle: IdleSteps,
}

fn invalid(field: impl Into<String>, value: impl std::fmt::Debug) -> GpuError {
    GpuError::InvalidInput {
        field: field.into(),
        value: format!("{value:?}"),
    }
}

impl GpuWorld {
    /// An empty world on `ctx`. Errs on a bad config, naming the field.
    pub fn new(ctx: &GpuContext, config: GpuWorldConfig) -> Result<Self, GpuError> {
        config.validate()?;
        let timer = if config.timestamps {
            StageTimer::new(ctx)
        } else {
            StageTimer::disabled(ctx)
        };
        Ok(Self {
            ctx: ctx.clone(),
            config,
            collision: GpuCollision::new(ctx, config.collision())?,
            solver: GpuSolver::new(ctx, Effects::of_scene(&[], &config.gravity))?,
            pool: BufferPool::new(ctx),
            bodies: Vec::new(),
            impulses: Vec::new(),
            stats: StatsRing::new(ctx),
            known_manifolds: None,
            pair_overflows: 0,
            readback: Readback::new(ctx),
            request: ReadRequest::default(),
            pending: VecDeque::new(),
            timer,
            steps: 0,
            source: ContactSource::Collision,
            host_count: 0,
            last_path: None,
            bytes_read: 0,
            sleep: GpuSleep::new(ctx),
            idle: IdleSteps::default(),
        })
    }

    /// The settings.
    pub fn config(&self) -> &GpuWorldConfig {
        &self.config
    }

    /// Replaces the solver settings from the next step on. Errs on a bad field, naming it.
    pub fn set_solver(&mut self, solver: tumble_solver::SolverConfig) -> Result<(), GpuError> {
        let config = GpuWorldConfig {
            solver,
            ..self.config
        };
        config.validate()?;
        if config != self.config {
            self.idle.changed();
        }
        self.config = config;
        Ok(())
    }

    /// Compiles in exactly `effects` from the next step on (instead of those derived from the
    /// bodies on upload): an effect forced off is left out even where the scene needs it.
    /// Turning sleep on starts every body awake with no rest time; turning it off wakes every
    /// sleeping body.
    pub fn set_effects(&mut self, effects: Effects) -> Result<(), GpuError> {
        if effects != self.effects() {
            self.idle.changed();
        }
        self.solver.set_effects(effects)?;
        if effects.sleep && !self.sleep.is_enabled() {
            let gpu: Vec<GpuBody> = self.bodies.iter().map(gpu_body).collect();
            self.sleep.enable(&gpu, self.config.dt)?;
        } else if !effects.sleep && self.sleep.is_enabled() {
            self.flush_impulses()?;
            // An empty world has no body buffers, and no body to wake.
            let restore = (!self.bodies.is_empty())
                .then(|| (self.pool.get(BODIES), self.collision.buffers().shapes));
            self.sleep.disable(restore)?;
        }
        Ok(())
    }

    /// The effects compiled in, sleep included.
    pub fn effects(&self) -> Effects {
        Effects {
            sleep: self.sleep.is_enabled(),
            ..self.solver.effects()
        }
    }

    /// Wakes body `i`'s island by the start of the next step (and restarts its rest time);
    /// a no-op for an awake body or with sleep off. Setting a pose or a velocity or applying
    /// an impulse does the same.
    pub fn wake_up(&mut self, i: usize) -> Result<(), GpuError> {
        self.check_body(i)?;
        self.idle.changed();
        self.sleep.queue_wake(i as u32);
        Ok(())
    }

    /// The sleep stage (for tests and tools: its island labels and rest times).
    pub fn sleep_stage(&self) -> &GpuSleep {
        &self.sleep
    }

    /// The device.
    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// Bodies uploaded.
    pub fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The solver path the last step took.
    pub fn last_path(&self) -> Option<SolvePath> {
        self.last_path
    }

    /// Bytes copied from the GPU for the host so far, by step readbacks and [`Self::read_now`]
    /// (the solver's own small count reads excluded): what reading only what was asked for
    /// saves is visible here.
    pub fn bytes_read(&self) -> u64 {
        self.bytes_read
    }

    /// Steps whose work was skipped because they would repeat an idle step (see
    /// [`super::idle`]).
    pub fn idle_steps(&self) -> u64 {
        self.idle.skipped_steps()
    }

    /// Times the pair buffers overflowed (and grew); the steps concerned missed pairs.
    pub fn pair_overflows(&self) -> u32 {
        self.pair_overflows
    }

    /// The solver stage (for tests and tools: its coloring and constraint buffers).
    pub fn solver(&self) -> &GpuSolver {
        &self.solver
    }

    /// Uploads every body (cold data, pose, velocities); body `i` is `bodies[i]` from now on.
    /// Warm starting and color seeds start over (indices may have been reassigned), and the
    /// pipelines are specialized for the effects these bodies use.
    pub fn set_bodies(&mut self, bodies: &[Body], states: &[BodyState]) -> Result<(), GpuError> {
        if states.len() != bodies.len() {
            return Err(invalid(
                "states.len()",
                format!("{} for {} bodies", states.len(), bodies.len()),
            ));
        }
        self.stats.reset()?;
        self.idle.changed();
        self.pending.clear();
        self.impulses.clear();
        self.known_manifolds = None;
        let gpu: Vec<GpuBody> = bodies.iter().map(gpu_body).collect();
        if !bodies.is_empty() {
            let poses: Vec<GpuPose> = bodies.iter().map(|b| gpu_pose(&b.pose)).collect();
            let velocities: Vec<GpuVelocity> = states.iter().map(gpu_velocity).collect();
            let shapes: Vec<_> = bodies.iter().map(gpu_shape).collect();
            self.collision.set_bodies(&poses, &velocities, &shapes)?;
            self.collision.forget_history();
            let bytes: &[u8] = bytemuck::cast_slice(&gpu);
            self.pool
                .ensure(BODIES, bytes.len() as u64, STORAGE_USAGE)?;
            self.ctx.queue.write_buffer(self.pool.get(BODIES), 0, bytes);
        }
        self.solver
            .set_effects(Effects::of_scene(bodies, &self.config.gravity))?;
        self.solver.forget_colors();
        self.sleep.reset(&gpu, self.config.dt)?;
        self.bodies = bodies.to_vec();
        Ok(())
    }

    fn check_body(&self, i: usize) -> Result<(), GpuError> {
        if i >= self.bodies.len() {
            return Err(invalid(
                "body",
                format!("{i} (the world has {} bodies)", self.bodies.len()),
            ));
        }
        Ok(())
    }

    /// Teleports body `i` (velocities kept). Takes effect before the next step.
    pub fn set_pose(&mut self, i: usize, pose: &Pose) -> Result<(), GpuError> {
        self.check_body(i)?;
        let finite = pose.translation.vector.iter().all(|c| c.is_finite())
            && pose.rotation.coords.iter().all(|c| c.is_finite());
        if !finite {
            return Err(invalid("pose", pose));
        }
        self.flush_impulses()?;
        self.idle.changed();
        self.sleep.queue_wake(i as u32);
        let offset = (i * std::mem::size_of::<GpuPose>()) as u64;
        let poses = self.collision.buffers().poses;
        self.ctx
            .queue
            .write_buffer(poses, offset, bytemuck::bytes_of(&gpu_pose(pose)));
        Ok(())
    }

    /// Sets body `i`'s linear and angular velocity. Takes effect before the next step.
    pub fn set_velocity(
        &mut self,
        i: usize,
        linear: &Vec3,
        angular: &Vec3,
    ) -> Result<(), GpuError> {
        self.check_body(i)?;
        if !linear.iter().all(|c| c.is_finite()) {
            return Err(invalid("linear_velocity", linear));
        }
        if !angular.iter().all(|c| c.is_finite()) {
            return Err(invalid("angular_velocity", angular));
        }
        self.flush_impulses()?;
        self.idle.changed();
        self.sleep.queue_wake(i as u32);
        let offset = (i * std::mem::size_of::<GpuVelocity>()) as u64;
        let velocity = gpu_velocity(&BodyState::moving(*linear, *angular));
        let velocities = self.collision.buffers().velocities;
        self.ctx
            .queue
            .write_buffer(velocities, offset, bytemuck::bytes_of(&velocity));
        Ok(())
    }

    /// Queues an impulse (N s, world) at a world point on body `i`, applied on the GPU at
    /// the start of the next step, in queue order (fixed and kinematic bodies ignore it).
    pub fn apply_impulse(
        &mut self,
        i: usize,
        impulse: &Vec3,
        point: &Point3,
    ) -> Result<(), GpuError> {
        self.check_body(i)?;
        if !impulse.iter().all(|c| c.is_finite()) {
            return Err(invalid("impulse", impulse));
        }
        if !point.iter().all(|c| c.is_finite()) {
            return Err(invalid("point", point));
        }
        self.idle.changed();
        self.sleep.queue_wake(i as u32);
        self.impulses.push(GpuImpulse {
            body: i as u32,
            impulse: [impulse.x, impulse.y, impulse.z, 0.0],
            point: [point.x, point.y, point.z, 0.0],
            ..Default::default()
        });
        Ok(())
    }

    /// Records the queued impulses (if any) and empties the queue.
    fn record_impulses(&mut self, encoder: &mut wgpu::CommandEncoder) {
        if self.impulses.is_empty() {
            return;
        }
        let queued = self.ctx.storage_buffer("queued impulses", &self.impulses);
        let kernel = &self.solver.pipelines().apply_impulses;
        let buffers = self.collision.buffers();
        let group = kernel.bind(
            &self.ctx,
            &ApplyImpulsesArgs {
                impulses: &queued,
                bodies: self.pool.get(BODIES),
                poses: buffers.poses,
                velocities: buffers.velocities,
            },
        );
        let mut pass = self.timer.begin_pass(encoder, "apply_impulses");
        kernel.dispatch_workgroups(&mut pass, &group, 1, 1);
        drop(pass);
        self.impulses.clear();
    }

    /// Submits the queued impulses now, so a later write of a pose or velocity lands after
    /// them, as the calls were made. The islands queued to wake wake first, as at the start
    /// of a step: an impulse skips a sleeping body (a fixed one to the kernel).
    fn flush_impulses(&mut self) -> Result<(), GpuError> {
        if self.impulses.is_empty() {
            return Ok(());
        }
        let mut encoder = self.encoder("impulses");
        self.timer.reset();
        let shapes = self.collision.buffers().shapes;
        self.sleep
            .record_wake(&mut encoder, &mut self.timer, self.pool.get(BODIES), shapes);
        self.record_impulses(&mut encoder);
        self.ctx.queue.submit([encoder.finish()]);
        Ok(())
    }

    fn encoder(&self, label: &str) -> wgpu::CommandEncoder {
        self.ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) })
    }

    /// Asks the next steps to copy `request` for reading (see [`Self::latest_snapshot`]).
    pub fn request_reads(&mut self, request: ReadRequest) {
        self.request = request;
    }

    /// Reads the two-steps-old manifold count (waiting for it if needed) and grows the pair
    /// buffers if that step overflowed.
    fn take_stats(&mut self) -> Result<(), GpuError> {
        let stats = self.stats.take_lagged()?;
        self.idle.observe(stats.as_ref());
        let Some(stats) = stats else {
            return Ok(());
        };
        let work = stats.work;
        self.known_manifolds = Some(work.count);
        if work.requested > work.capacity {
            self.pair_overflows += 1;
            let wanted = work.requested.saturating_add(work.requested / 4);
            self.collision.reserve_pairs(wanted)?;
        }
        Ok(())
    }

    /// The solver path of the next step: decided by a count that is itself a result of the
    /// simulation (never by timing), so runs are reproducible.
    fn choose_path(&self) -> SolvePath {
        match self.config.path {
            PathPolicy::Always(path) => path,
            PathPolicy::Auto => {
                let bodies = self.bodies.len() as u32;
                let manifolds = self
                    .known_manifolds
                    .unwrap_or(bodies.saturating_mul(ESTIMATED_PAIRS_PER_BODY));
                SolvePath::choose(bodies, manifolds)
            }
        }
    }

    fn params(&self) -> StepParams {
        StepParams::new(
            &self.config.solver,
            self.config.dt,
            &self.config.gravity,
            self.bodies.len() as u32,
            self.solver.effects().restitution,
        )
    }

    /// One step, entirely on the GPU, in one command encoder and one submit.
    pub fn step(&mut self) -> Result<(), GpuError> {
        if self.bodies.is_empty() {
            self.steps += 1;
            return Ok(());
        }
        self.take_stats()?;
        let path = self.choose_path();
        if self.config.skip_idle_steps && self.idle.can_skip() {
            // Repeats an idle step: only the stats copy and the requested reads.
            self.idle.skipped();
            self.timer.reset();
            let encoder = self.encoder("tumble idle step");
            return self.finish_step(encoder, self.last_path.unwrap_or(path));
        }
        let params = self.params();
        let mut encoder = self.encoder("tumble step");
        self.timer.reset();
        // Islands wake before the impulses, which skip bodies that are not dynamic.
        let shapes = self.collision.buffers().shapes;
        self.sleep
            .record_wake(&mut encoder, &mut self.timer, self.pool.get(BODIES), shapes);
        self.record_impulses(&mut encoder);
        self.collision.record(&mut encoder, &mut self.timer)?;
        let buffers = self.collision.buffers();
        let inputs = SolverInputs {
            bodies: self.pool.get(BODIES),
            poses: buffers.poses,
            velocities: buffers.velocities,
            manifolds: buffers.manifolds,
            contacts: buffers.contacts,
            contact_work: buffers.pair_work,
            body_count: self.bodies.len() as u32,
            contact_capacity: self.collision.pair_capacity(),
        };
        self.solver
            .record(&mut encoder, &mut self.timer, &inputs, &params.params, path)?;
        let sleep_inputs = SleepInputs {
            bodies: self.pool.get(BODIES),
            shapes: buffers.shapes,
            velocities: buffers.velocities,
            pair_work: buffers.pair_work,
            manifolds: buffers.manifolds,
            aabbs: buffers.aabbs,
        };
        self.sleep
            .record_update(&mut encoder, &mut self.timer, &sleep_inputs);
        self.source = ContactSource::Collision;
        self.finish_step(encoder, path)
    }

    /// Copies for the requested reads, the stats copy, timestamps, submit.
    fn finish_step(
        &mut self,
        mut encoder: wgpu::CommandEncoder,
        path: SolvePath,
    ) -> Result<(), GpuError> {
        let (_, _, work, _) = self.contact_buffers();
        let active = self.sleep.active_count();
        self.stats
            .record(&mut encoder, &work, active, self.idle.changes());
        let read = if self.request == ReadRequest::default() {
            None
        } else {
            let manifolds = match self.source {
                ContactSource::Host => self.host_count,
                ContactSource::Collision => {
                    let known = self.known_manifolds.unwrap_or(0);
                    (known + (known as f32 * READ_HEADROOM) as u32).max(READ_MIN_MANIFOLDS)
                }
            };
            Some(self.record_read(&mut encoder, self.request, manifolds)?)
        };
        self.timer.resolve(&mut encoder);
        let index = self.ctx.queue.submit([encoder.finish()]);
        self.stats.submitted(index);
        if let Some((slot, regions, islands_copied)) = read {
            let ticket = self.readback.submitted(slot);
            // Two staging slots: a third pending read would reuse the oldest one's.
            if self.pending.len() == 2 {
                self.pending.pop_front();
            }
            self.pending.push_back(PendingRead {
                ticket,
                regions,
                request: self.request,
                step: self.steps + 1,
                islands_copied,
            });
        }
        self.last_path = Some(path);
        self.steps += 1;
        Ok(())
    }

    /// Records copies of `request` (with up to `manifolds` manifolds) into a staging slot.
    fn record_read(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        request: ReadRequest,
        manifolds: u32,
    ) -> Result<(usize, Vec<Region>, bool), GpuError> {
        let n = self.bodies.len() as u64;
        let (manifold_buffer, point_buffer, work, capacity) = self.contact_buffers();
        let m = u64::from(manifolds.min(capacity));
        let sizes = ReadSizes::new(n, m);
        let slot = self.readback.begin(sizes.total(&request))?;
        let mut regions = Vec::new();
        let buffers = self.collision.buffers();
        let rb = &mut self.readback;
        if request.poses {
            regions.push(rb.copy(encoder, slot, buffers.poses, 0, sizes.poses));
        }
        if request.velocities {
            regions.push(rb.copy(encoder, slot, buffers.velocities, 0, sizes.velocities));
        }
        if request.contacts {
            regions.push(rb.copy(encoder, slot, &work, 0, sizes.work));
            regions.push(rb.copy(encoder, slot, &manifold_buffer, 0, sizes.manifolds));
            regions.push(rb.copy(encoder, slot, &point_buffer, 0, sizes.points));
            regions.push(rb.copy(
                encoder,
                slot,
                self.solver.constraints(),
                0,
                sizes.constraints,
            ));
            regions.push(rb.copy(encoder, slot, self.solver.tilts(), 0, sizes.tilts));
        }
        let islands = self.sleep.island_labels().filter(|_| request.sleeping);
        if let Some(islands) = islands {
            regions.push(rb.copy(encoder, slot, islands, 0, sizes.islands));
        }
        self.bytes_read += regions.iter().map(|r| r.len).sum::<u64>();
        Ok((slot, regions, islands.is_some()))
    }

    /// The most recent requested read whose copy has arrived, without waiting (older ones
    /// are dropped); `None` when none has arrived yet.
    pub fn latest_snapshot(&mut self) -> Option<Result<Snapshot, GpuError>> {
        let mut latest = None;
        while let Some(oldest) = self.pending.front() {
            let Some(bytes) = self.readback.try_read(&oldest.ticket, &oldest.regions) else {
                break;
            };
            let done = self.pending.pop_front().expect("front exists");
            let n = self.bodies.len();
            latest = Some(bytes.map(|b| decode(&done, n, b)));
        }
        latest
    }

    /// Waits for the most recent requested read (older ones are dropped).
    pub fn wait_snapshot(&mut self) -> Result<Option<Snapshot>, GpuError> {
        while self.pending.len() > 1 {
            self.pending.pop_front();
        }
        let Some(last) = self.pending.pop_front() else {
            return Ok(None);
        };
        // Polls until the map callback has run: another user of the device may be running it
        // in its own poll when a plain wait returns.
        let deadline = std::time::Instant::now() + READ_TIMEOUT;
        loop {
            if let Some(bytes) = self.readback.try_read(&last.ticket, &last.regions) {
                return Ok(Some(decode(&last, self.bodies.len(), bytes?)));
            }
            if std::time::Instant::now() > deadline {
                return Err(GpuError::Device("readback was not mapped in time".into()));
            }
            self.ctx.wait_idle()?;
        }
    }

    /// Reads `request` from the current state now, blocking (queued impulses are applied
    /// first). Contacts are the last step's, complete.
    pub fn read_now(&mut self, request: ReadRequest) -> Result<Snapshot, GpuError> {
        self.flush_impulses()?;
        let n = self.bodies.len() as u64;
        let mut snapshot = Snapshot {
            step: self.steps,
            ..Default::default()
        };
        if n == 0 {
            return Ok(snapshot);
        }
        let buffers = self.collision.buffers();
        if request.poses {
            snapshot.poses = self.ctx.read_buffer(buffers.poses, 0, n)?;
        }
        if request.velocities {
            snapshot.velocities = self.ctx.read_buffer(buffers.velocities, 0, n)?;
        }
        if request.contacts && self.steps > 0 {
            let (manifolds, points, work, _) = self.contact_buffers();
            let list: Vec<WorkList> = self.ctx.read_buffer(&work, 0, 1)?;
            let count = u64::from(list[0].count);
            snapshot.contacts = Some(ContactSnapshot {
                work: list[0],
                manifolds: self.ctx.read_buffer(&manifolds, 0, count)?,
                points: self
                    .ctx
                    .read_buffer(&points, 0, count * u64::from(MAX_MANIFOLD_POINTS))?,
                constraints: self.ctx.read_buffer(self.solver.constraints(), 0, count)?,
                tilts: self.ctx.read_buffer(self.solver.tilts(), 0, count)?,
            });
        }
        self.bytes_read += snapshot_bytes(&snapshot);
        if request.sleeping {
            snapshot.sleeping = match self.sleep.island_labels() {
                Some(islands) => {
                    let labels: Vec<u32> = self.ctx.read_buffer(islands, 0, n)?;
                    self.bytes_read += std::mem::size_of_val(labels.as_slice()) as u64;
                    labels.iter().map(|&l| l != AWAKE).collect()
                }
                None => vec![false; n as usize],
            };
        }
        Ok(snapshot)
    }

    /// GPU time per stage of the last step, seconds (empty without timestamps). Blocks.
    pub fn timings(&mut self) -> Result<Vec<(&'static str, f64)>, GpuError> {
        self.timer.read()
    }
}

/// Bytes held by a snapshot's arrays.
fn snapshot_bytes(s: &Snapshot) -> u64 {
    fn bytes<T>(v: &[T]) -> u64 {
        std::mem::size_of_val(v) as u64
    }
    let contacts = s.contacts.as_ref().map_or(0, |c| {
        std::mem::size_of::<WorkList>() as u64
            + bytes(&c.manifolds)
            + bytes(&c.points)
            + bytes(&c.constraints)
            + bytes(&c.tilts)
    });
    bytes(&s.poses) + bytes(&s.velocities) + contacts
}
