//! [`GpuWorld`]: the whole step on the GPU. Bodies are uploaded once; each step records the
//! wake, then walks `tumble_solver::Stage::ALL` (`update_aabbs -> broad_phase ->
//! narrow_phase (with matching) -> color -> solve -> finish -> sleep`) into command buffers
//! submitted in order (the wide solve path submits what it has before each substep, so the GPU
//! runs while the host records), waits for nothing inside the step, and reads nothing back
//! unless asked (asynchronously, double-buffered).

use std::collections::VecDeque;

use tumble_geometry::{Point3, Pose, Vec3};
use tumble_solver::{Body, BodyState, Stage};

use crate::buffer_pool::{BufferPool, STORAGE_USAGE};
use crate::collision::{GpuCollision, StepBuffers};
use crate::error::invalid;
use crate::layout::{GpuContact, GpuManifold, GpuPose, GpuVelocity, WorkList};
use crate::readback::{Readback, Region};
use crate::sleep::GpuSleep;
use crate::sleep::constants::AWAKE;
use crate::solver::constants::GRAPH_COLOR_COUNT;
use crate::solver::convert::{gpu_body, gpu_manifold, gpu_shape, gpu_tilt, gpu_velocity};
use crate::solver::layout::{GpuBody, GpuImpulse, GpuTilt};
use crate::solver::path::{WORLDS_MAX_BODIES, WORLDS_MAX_TOTAL_BODIES};
use crate::solver::{Effects, GpuSolver, SolvePath, SolverInputs, StepParams, SubstepDispatch};
use crate::{GpuContext, GpuError, MAX_MANIFOLD_POINTS, StageTimer};

use super::config::{ColorDispatch, GpuWorldConfig, PathPolicy};
use super::events::EventStage;
use super::idle::IdleSteps;
use super::read_plan::{PendingRead, decode};
use super::snapshot::{ContactSnapshot, ReadRequest, Snapshot};
use super::stats_ring::{STATS_LAG, StatsRing, StatsSources};
use crate::kernels::contact_events::ContactEventList;

pub use draw::DrawBuffers;
pub use saved::{GpuWorldState, SavedCollision, SavedIdle, SavedStats};

mod bodies;
mod checked;
mod draw;
mod host_contacts;
mod reads;
mod saved;
mod summary;

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
    /// Each body's world ([`Self::set_bodies_in_worlds`]); empty when all are in world 0.
    worlds: Vec<u32>,
    /// Bodies of the largest world.
    max_world_bodies: u32,
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
    /// The contact-event stage, while events are on.
    events: Option<EventStage>,
    /// The motion check and the last step's checkpoint, while the check is on.
    check: Option<checked::MotionCheck>,
    /// The contact summary's kernel and output, once a read asked for it.
    summary: Option<summary::SummaryStage>,
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
        let mut solver = GpuSolver::new(ctx, Effects::of_bodies(&[], &config.gravity))?;
        solver.set_fused_memory(config.fused_memory);
        solver.set_world_grouping(config.world_grouping);
        solver.set_warm_start_sweep(config.warm_start_sweep);
        solver.set_substep_dispatch(config.substep_dispatch)?;
        Ok(Self {
            ctx: ctx.clone(),
            config,
            collision: GpuCollision::new(ctx, config.collision())?,
            solver,
            pool: BufferPool::new(ctx),
            bodies: Vec::new(),
            worlds: Vec::new(),
            max_world_bodies: 0,
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
            events: None,
            check: None,
            summary: None,
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
            let restore = (!self.bodies.is_empty()).then(|| {
                (
                    self.pool.get(BODIES),
                    self.collision.buffers(self.pool.get(BODIES)).shapes,
                )
            });
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

    /// Bytes of the device buffers the world's stages hold in their pools (bodies, collision,
    /// solver, sleep) and, with the motion check on, its shadow copies of them: what the world
    /// costs in GPU memory, readback staging and small parameter blocks aside. The sum of
    /// [`Self::buffer_sizes`].
    pub fn buffer_bytes(&self) -> u64 {
        self.buffer_sizes().iter().map(|&(_, _, bytes)| bytes).sum()
    }

    /// Every pooled device buffer of the world as (pool, buffer name, bytes): the pools
    /// `world`, `collision`, `solver`, `sleep` and, with the motion check on, the shadow
    /// copies the check keeps of them (`check world`, ...), and the contact summary's 32 bytes
    /// once a read asked for it (`readback`). For memory reports
    /// (docs/gpu.md, "Memory per body").
    pub fn buffer_sizes(&self) -> Vec<(&'static str, &'static str, u64)> {
        let stages = [
            ("world", self.pool.sizes()),
            ("collision", self.collision.buffer_sizes()),
            ("solver", self.solver.pool().sizes()),
            ("sleep", self.sleep.buffer_sizes()),
        ];
        let mut out: Vec<_> = stages
            .into_iter()
            .flat_map(|(pool, sizes)| sizes.into_iter().map(move |(n, b)| (pool, n, b)))
            .collect();
        out.extend(self.shadow_sizes());
        if self.summary.is_some() {
            out.push((
                "readback",
                "contact_summary",
                crate::kernels::contact_summary::CONTACT_SUMMARY_BYTES,
            ));
        }
        out
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

    /// Reads the two-steps-old manifold count (waiting for it if needed) and grows the pair
    /// buffers if that step overflowed.
    fn take_stats(&mut self) -> Result<(), GpuError> {
        let stats = self.stats.take_lagged()?;
        self.idle.observe(stats.as_ref());
        let colors = match self.config.color_dispatch {
            ColorDispatch::InUse => stats.as_ref().and_then(|s| s.colors),
            ColorDispatch::All => Some(GRAPH_COLOR_COUNT),
            ColorDispatch::First(colors) => Some(colors),
        };
        if let Some(colors) = colors {
            self.solver.set_color_dispatches(colors)?;
        }
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
        if stats.substep_wait_gave_up {
            // Never expected (every wait of solve_step is for chunks that running workgroups
            // took), but a wait that gave up means that step's results may be wrong: say so,
            // and dispatch per color from now on.
            self.config.substep_dispatch = SubstepDispatch::PerColor;
            self.solver
                .set_substep_dispatch(SubstepDispatch::PerColor)?;
            return Err(GpuError::Device(format!(
                "a wait of the one-dispatch substeps (solve_step) gave up after {} polls in the \
                 step {STATS_LAG} steps back: that step's results may be wrong; the world now \
                 dispatches its substeps per color",
                crate::solver::solve_step::SOLVE_STEP_WAIT_LIMIT
            )));
        }
        Ok(())
    }

    /// The solver path of the next step: decided by a count that is itself a result of the
    /// simulation (never by timing), so runs are reproducible.
    fn choose_path(&self) -> SolvePath {
        // The fused path numbers constraints as one world's: a batch takes the wide path, or
        // one fused workgroup per group of worlds while its worlds are small (or when asked for
        // the fused path).
        if self.solver.world_count() > 1 {
            let per_world = match self.config.path {
                PathPolicy::Always(SolvePath::Wide) => false,
                PathPolicy::Always(_) => true,
                PathPolicy::Auto => {
                    self.max_world_bodies <= WORLDS_MAX_BODIES
                        && self.bodies.len() as u32 <= WORLDS_MAX_TOTAL_BODIES
                }
            };
            return if per_world {
                SolvePath::Worlds
            } else {
                SolvePath::Wide
            };
        }
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

    /// One step, entirely on the GPU, submitted without waiting for the GPU.
    pub fn step(&mut self) -> Result<(), GpuError> {
        // A lost device or an error from an earlier submission: nothing of this step runs.
        self.ctx.check_health()?;
        if self.bodies.is_empty() {
            self.steps += 1;
            return Ok(());
        }
        let before = self.before_step();
        self.take_stats()?;
        let path = self.choose_path();
        if self.config.skip_idle_steps && self.idle.can_skip() {
            // Repeats an idle step: only the stats copy and the requested reads.
            self.idle.skipped();
            self.timer.reset();
            let mut encoder = self.ctx.encoder("tumble idle step");
            if let Some(events) = &mut self.events {
                events.record_idle(&mut encoder);
            }
            return self.finish_step(encoder, self.last_path.unwrap_or(path), false);
        }
        let params = self.params();
        let mut encoder = self.ctx.encoder("tumble step");
        self.timer.reset();
        self.record_checkpoint(&mut encoder, before);
        self.record_wakes_and_impulses(&mut encoder);
        // The step's stages in the one order every backend runs them. A recorder may record
        // several consecutive stages (the collision stages share their parity and clears, the
        // fused solve path is one kernel for color, solve and finish): its first stage records
        // them all, the others record nothing of their own.
        for stage in Stage::ALL {
            match stage {
                // update_aabbs, broad_phase, narrow_phase.
                Stage::UpdateAabbs => self.collision.record(&mut encoder, &mut self.timer)?,
                Stage::BroadPhase | Stage::NarrowPhase => {}
                // color, solve (prepare, substeps, restitution), finish (stored impulses, poses).
                Stage::Color => {
                    let inputs = SolverInputs {
                        buffers: self.collision.buffers(self.pool.get(BODIES)),
                        body_count: self.bodies.len() as u32,
                        contact_capacity: self.collision.pair_capacity(),
                    };
                    self.solver.record(
                        &mut encoder,
                        &mut self.timer,
                        &inputs,
                        &params.params,
                        path,
                    )?;
                }
                Stage::Solve | Stage::Finish => {}
                Stage::Sleep => {
                    let buffers = self.collision.buffers(self.pool.get(BODIES));
                    self.sleep
                        .record_update(&mut encoder, &mut self.timer, &buffers);
                }
            }
        }
        if let Some(events) = &mut self.events {
            events.record(&self.ctx, &mut encoder, &self.collision);
        }
        self.record_motion_check(&mut encoder);
        self.source = ContactSource::Collision;
        self.finish_step(encoder, path, true)
    }

    /// Turns the contact-event stage on or off from the next step on. On, each step ends
    /// with `contact_begins` and `contact_ends` (`crate::kernels::contact_events`), read by
    /// [`Self::read_contact_events`]; off (the default), nothing is recorded for them.
    pub fn set_contact_events(&mut self, on: bool) -> Result<(), GpuError> {
        match (on, self.events.is_some()) {
            (true, false) => self.events = Some(EventStage::new(&self.ctx)?),
            (false, true) => self.events = None,
            _ => {}
        }
        Ok(())
    }

    /// The last step's contact events and touching pairs (dense body indices), waiting for
    /// the step, with whether the GPU compared the step with the one before: `false` when
    /// the stage did not run after that step (events just turned on, an empty world, steps
    /// with host manifolds) or when its pairs were dropped since (bodies uploaded again, pair
    /// buffers grown); the events are then void and the touching pairs are to be compared on
    /// the host. `None` while events are off.
    pub fn read_contact_events(&mut self) -> Result<Option<(ContactEventList, bool)>, GpuError> {
        let Some(events) = &self.events else {
            return Ok(None);
        };
        if self.bodies.is_empty() || self.source == ContactSource::Host {
            return Ok(Some((ContactEventList::default(), false)));
        }
        let (list, compared, bytes) = events.read(&self.ctx)?;
        self.bytes_read += bytes;
        Ok(Some((list, compared)))
    }

    /// Copies for the requested reads, the stats copy, timestamps, submit. `solved`: the
    /// step recorded the solver stage along `path` (not an idle step's repeat).
    fn finish_step(
        &mut self,
        mut encoder: wgpu::CommandEncoder,
        path: SolvePath,
        solved: bool,
    ) -> Result<(), GpuError> {
        let (_, _, work, _) = self.contact_buffers();
        let sources = StatsSources {
            active: self.sleep.active_count(),
            color_counts: (solved && path == SolvePath::Wide).then(|| self.solver.color_counts()),
            substep_fault: (solved && path == SolvePath::Wide)
                .then(|| self.solver.substep_fault())
                .flatten(),
        };
        self.stats
            .record(&mut encoder, &work, sources, self.idle.changes());
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
        let index = self.ctx.submit(encoder)?;
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

    /// GPU time per stage of the last step, seconds (empty without timestamps). Blocks.
    pub fn timings(&mut self) -> Result<Vec<(&'static str, f64)>, GpuError> {
        self.timer.read()
    }
}
