//! [`GpuSleep`]: the sleep stage's buffers and its two places in a step, recorded into the
//! step's command encoder: [`GpuSleep::record_wake`] before the collision stages (islands
//! flagged last step or by the host wake up) and [`GpuSleep::record_update`] after the solver
//! (rest timers, the island search, islands falling asleep). Nothing is read back inside a
//! step; the manifold kernels are dispatched indirectly from the pair work list.

use crate::buffer_pool::{BufferPool, STORAGE_USAGE, UNIFORM_USAGE};
use crate::collision::StepBuffers;
use crate::kernel::Kernel;
use crate::layout::DispatchArgs;
use crate::solver::constants::BODY_KINEMATIC;
use crate::solver::layout::GpuBody;
use crate::{GpuContext, GpuError, StageTimer};

use super::constants::{AWAKE, ISLAND_ROUNDS};
use super::layout::SleepParams;
use super::pipelines::SleepPipelines;
use super::plan_search::{BODY_GROUPS_OFFSET, LINK_GROUPS_OFFSET};

/// Timer name of the pass that wakes flagged islands.
pub const SLEEP_WAKE: &str = "sleep: wake";
/// Timer name of the pass that updates rest times and puts islands to sleep.
pub const SLEEP_ISLANDS: &str = "sleep: islands";

// The pool's buffers are named as the kernels' bindings are, so the kernels' arguments are
// looked up by name (`Kernel::bind_named`).
const PARAMS: &str = "params";
const AWAKE_BODIES: &str = "awake_bodies";
const ISLAND: &str = "island";
const REST_TIME: &str = "rest_time";
const LABELS: &str = "labels";
/// The two copies the rounds hook into, in turn (`next_labels` and `spare`).
const NEXT_LABELS: [&str; 2] = ["next_labels 0", "next_labels 1"];
const SHORTEST_REST: &str = "shortest_rest";
const WAKE: &str = "wake";
const UNFINISHED: &str = "unfinished";
const KINEMATIC: &str = "kinematic";
const READY: &str = "ready";
const SEARCH_GROUPS: &str = "search_groups";
const ACTIVE: &str = "moving";

/// Pair buffer sets the collision stages alternate between (this step's and last step's).
const PAIR_SETS: usize = 2;

/// The bind groups of one set of inputs.
#[derive(Debug)]
struct Groups {
    key: (u64, Vec<wgpu::Buffer>),
    update_rest: wgpu::BindGroup,
    touch_sleepers: wgpu::BindGroup,
    kinematic_wake: wgpu::BindGroup,
    plan_search: wgpu::BindGroup,
    /// Round `r` hooks into `NEXT_LABELS[r % 2]`.
    hook_labels: [wgpu::BindGroup; 2],
    /// Round `r` jumps from `NEXT_LABELS[r % 2]` and leaves the spare in the other one.
    jump_labels: [wgpu::BindGroup; 2],
    check_labels: wgpu::BindGroup,
    island_rest: wgpu::BindGroup,
    fall_asleep: wgpu::BindGroup,
}

/// The sleep stage of a GPU world: off (no buffers, nothing recorded) until enabled.
#[derive(Debug)]
pub struct GpuSleep {
    ctx: GpuContext,
    pipelines: Option<SleepPipelines>,
    pool: BufferPool,
    body_count: u32,
    kinematic_count: u32,
    queued: Vec<u32>,
    /// Bind groups of the last input sets: the collision stages alternate between two pair
    /// buffer sets, so two are kept.
    groups: Vec<Groups>,
    /// The `wake_islands` bind group, by pool generation and solver bodies and shapes.
    wake_group: Option<(WakeKey, wgpu::BindGroup)>,
}

type WakeKey = (u64, wgpu::Buffer, wgpu::Buffer);

impl GpuSleep {
    /// The stage, off.
    pub fn new(ctx: &GpuContext) -> Self {
        Self {
            ctx: ctx.clone(),
            pipelines: None,
            pool: BufferPool::new(ctx),
            body_count: 0,
            kinematic_count: 0,
            queued: Vec::new(),
            groups: Vec::new(),
            wake_group: None,
        }
    }

    /// The stage's pooled device buffers by name, with their sizes in bytes.
    pub(crate) fn buffer_sizes(&self) -> Vec<(&'static str, u64)> {
        self.pool.sizes()
    }

    /// True when the stage runs in each step.
    pub fn is_enabled(&self) -> bool {
        self.pipelines.is_some()
    }

    /// Turns the stage on (building its pipelines on first use on this device) with every
    /// body awake and no rest time. `awake_bodies` are the bodies as uploaded; `dt` the step.
    pub fn enable(&mut self, awake_bodies: &[GpuBody], dt: f32) -> Result<(), GpuError> {
        if self.pipelines.is_none() {
            self.pipelines = Some(SleepPipelines::build(|spec| Kernel::new(&self.ctx, spec))?);
        }
        self.reset(awake_bodies, dt)
    }

    /// Every body awake with no rest time, for `awake_bodies` (after an upload). A no-op
    /// while the stage is off.
    pub fn reset(&mut self, awake_bodies: &[GpuBody], dt: f32) -> Result<(), GpuError> {
        if !self.is_enabled() {
            return Ok(());
        }
        let n = awake_bodies.len() as u32;
        let per_body = u64::from(n.max(1)) * 4;
        let body_bytes = std::mem::size_of_val(awake_bodies) as u64;
        let pool = &mut self.pool;
        let params = std::mem::size_of::<SleepParams>() as u64;
        pool.ensure(PARAMS, params, UNIFORM_USAGE)?;
        let search_groups = 2 * std::mem::size_of::<DispatchArgs>() as u64;
        let sizes = [
            (AWAKE_BODIES, body_bytes),
            (ISLAND, per_body),
            (REST_TIME, per_body),
            (LABELS, per_body),
            (SHORTEST_REST, per_body),
            (WAKE, per_body),
            (NEXT_LABELS[0], per_body),
            (NEXT_LABELS[1], per_body),
            (UNFINISHED, 4),
            (READY, 4),
            (ACTIVE, 4),
            (SEARCH_GROUPS, search_groups),
        ];
        pool.ensure_all(&sizes, STORAGE_USAGE)?;
        let kinematic: Vec<u32> = (0..n)
            .filter(|&i| awake_bodies[i as usize].kind == BODY_KINEMATIC)
            .collect();
        let kinematic_bytes = std::mem::size_of_val(kinematic.as_slice()) as u64;
        pool.ensure(KINEMATIC, kinematic_bytes, STORAGE_USAGE)?;
        let queue = &self.ctx.queue;
        queue.write_buffer(pool.get(KINEMATIC), 0, bytemuck::cast_slice(&kinematic));
        let (body_groups_x, body_groups_y) = crate::constants::workgroups_for(n);
        let params = SleepParams {
            body_count: n,
            dt,
            kinematic_count: kinematic.len() as u32,
            body_groups_x,
            body_groups_y,
            ..Default::default()
        };
        queue.write_buffer(pool.get(PARAMS), 0, bytemuck::bytes_of(&params));
        queue.write_buffer(
            pool.get(AWAKE_BODIES),
            0,
            bytemuck::cast_slice(awake_bodies),
        );
        let awake = vec![AWAKE; n as usize];
        queue.write_buffer(pool.get(ISLAND), 0, bytemuck::cast_slice(&awake));
        let zeros = vec![0u32; n as usize];
        queue.write_buffer(pool.get(REST_TIME), 0, bytemuck::cast_slice(&zeros));
        queue.write_buffer(pool.get(WAKE), 0, bytemuck::cast_slice(&zeros));
        self.body_count = n;
        self.kinematic_count = kinematic.len() as u32;
        self.queued.clear();
        Ok(())
    }

    /// The stage's buffers (none while it is off) and the bodies queued to wake, for a saved
    /// world (blocking).
    pub(crate) fn save_state(
        &self,
    ) -> Result<(Vec<crate::buffer_pool::SavedBuffer>, Vec<u32>), GpuError> {
        let buffers = if self.is_enabled() {
            self.pool.save()?
        } else {
            Vec::new()
        };
        Ok((buffers, self.queued.clone()))
    }

    /// Takes what [`Self::save_state`] gave, after [`Self::enable`] for the same bodies when
    /// the saved stage was on. Errs when one is on and the other off.
    pub(crate) fn load_state(
        &mut self,
        buffers: &[crate::buffer_pool::SavedBuffer],
        queued: &[u32],
    ) -> Result<(), GpuError> {
        if buffers.is_empty() == self.is_enabled() {
            return Err(GpuError::InvalidInput {
                field: "sleep buffers".into(),
                value: format!(
                    "{} saved while the sleep stage is {}",
                    buffers.len(),
                    if self.is_enabled() { "on" } else { "off" }
                ),
            });
        }
        if self.is_enabled() {
            self.pool.load(buffers)?;
        }
        if let Some(&i) = queued.iter().find(|&&i| i >= self.body_count) {
            return Err(GpuError::InvalidInput {
                field: "queued wakes".into(),
                value: format!("body {i} of {}", self.body_count),
            });
        }
        self.queued = queued.to_vec();
        Ok(())
    }

    /// The bodies queued to wake at the start of the next step.
    pub(crate) fn queued(&self) -> &[u32] {
        &self.queued
    }

    /// Puts back a queue [`Self::queued`] gave (a step undone).
    pub(crate) fn set_queued(&mut self, queued: Vec<u32>) {
        self.queued = queued;
    }

    /// Records a copy of the state buffers into `shadow` (none while off).
    pub(crate) fn record_checkpoint(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        shadow: &mut BufferPool,
    ) {
        if self.is_enabled() {
            self.pool.record_checkpoint(encoder, shadow);
        }
    }

    /// Records the copy of `shadow` back (nothing while off).
    pub(crate) fn copy_back(&self, encoder: &mut wgpu::CommandEncoder, shadow: &BufferPool) {
        if self.is_enabled() {
            self.pool.copy_back(encoder, shadow);
        }
    }

    /// Turns the stage off, waking every sleeping body first, in a submit of its own: `restore`
    /// holds the solver's bodies and the collision shapes to restore them in (`None` for a
    /// world without body buffers yet).
    pub fn disable(
        &mut self,
        restore: Option<(&wgpu::Buffer, &wgpu::Buffer)>,
    ) -> Result<(), GpuError> {
        if !self.is_enabled() {
            return Ok(());
        }
        if let Some((bodies, shapes)) = restore.filter(|_| self.body_count > 0) {
            let every = vec![1u32; self.body_count as usize];
            self.ctx
                .queue
                .write_buffer(self.pool.get(WAKE), 0, bytemuck::cast_slice(&every));
            let mut encoder = self.ctx.encoder("sleep off");
            let mut timer = StageTimer::disabled(&self.ctx);
            self.record_wake(&mut encoder, &mut timer, bodies, shapes);
            self.ctx.queue.submit([encoder.finish()]);
        }
        self.pipelines = None;
        self.groups.clear();
        self.wake_group = None;
        Ok(())
    }

    /// Replaces body `i`'s record in the stage's copy of the bodies as uploaded (after its
    /// force, torque, gravity scale or groups changed); the island must be queued to wake
    /// ([`Self::queue_wake`]), which restores the record in the solver's bodies. A no-op
    /// while the stage is off.
    pub fn update_awake_body(&mut self, i: u32, body: &GpuBody) {
        if self.is_enabled() && i < self.body_count {
            let offset = u64::from(i) * std::mem::size_of::<GpuBody>() as u64;
            self.ctx.queue.write_buffer(
                self.pool.get(AWAKE_BODIES),
                offset,
                bytemuck::bytes_of(body),
            );
        }
    }

    /// Wakes body `i`'s island (if it sleeps) and restarts its rest time at the start of the
    /// next step. A no-op while the stage is off.
    pub fn queue_wake(&mut self, i: u32) {
        if self.is_enabled() {
            self.queued.push(i);
        }
    }

    /// `array<u32>`: each body's island label, [`AWAKE`] for an awake body (`None` while
    /// the stage is off).
    pub fn island_labels(&self) -> Option<&wgpu::Buffer> {
        self.is_enabled().then(|| self.pool.get(ISLAND))
    }

    /// `array<f32>`: each body's rest time, s (`None` while the stage is off).
    pub fn rest_times(&self) -> Option<&wgpu::Buffer> {
        self.is_enabled().then(|| self.pool.get(REST_TIME))
    }

    /// `array<u32>`: the last island search's labels (`None` while the stage is off).
    pub fn search_labels(&self) -> Option<&wgpu::Buffer> {
        self.is_enabled().then(|| self.pool.get(LABELS))
    }

    /// One `u32`: the bodies the last recorded wake left to move (every body not fixed:
    /// awake dynamic bodies and kinematic ones; `None` while the stage is off).
    pub fn active_count(&self) -> Option<&wgpu::Buffer> {
        self.is_enabled().then(|| self.pool.get(ACTIVE))
    }

    /// One `u32`, nonzero when the last island search did not finish (`None` while off).
    pub fn unfinished_flag(&self) -> Option<&wgpu::Buffer> {
        self.is_enabled().then(|| self.pool.get(UNFINISHED))
    }

    /// The index in `groups` of the bind groups over `inputs`, built if missing.
    fn ensure_groups(&mut self, inputs: &StepBuffers<'_>) -> usize {
        let key = (
            self.pool.generation(),
            vec![
                inputs.bodies.clone(),
                inputs.shapes.clone(),
                inputs.velocities.clone(),
                inputs.contact_work.clone(),
                inputs.manifolds.clone(),
                inputs.aabbs.clone(),
            ],
        );
        if let Some(found) = self.groups.iter().position(|g| g.key == key) {
            return found;
        }
        let k = self.pipelines.as_ref().expect("enabled");
        let (ctx, p) = (&self.ctx, &self.pool);
        // The step's buffers, then the pool's; `next` picks the copy a round hooks into.
        let buffer = |next: usize| {
            move |name: &'static str| match name {
                "work" => inputs.contact_work,
                "manifolds" => inputs.manifolds,
                "velocities" => inputs.velocities,
                "aabbs" => inputs.aabbs,
                "bodies" => inputs.bodies,
                "shapes" => inputs.shapes,
                "next_labels" => p.get(NEXT_LABELS[next]),
                "spare" => p.get(NEXT_LABELS[1 - next]),
                name => p.get(name),
            }
        };
        let groups = Groups {
            update_rest: k.update_rest.bind_named(ctx, buffer(0)),
            touch_sleepers: k.touch_sleepers.bind_named(ctx, buffer(0)),
            kinematic_wake: k.kinematic_wake.bind_named(ctx, buffer(0)),
            plan_search: k.plan_search.bind_named(ctx, buffer(0)),
            hook_labels: [0, 1].map(|next| k.hook_labels.bind_named(ctx, buffer(next))),
            jump_labels: [0, 1].map(|from| k.jump_labels.bind_named(ctx, buffer(from))),
            check_labels: k.check_labels.bind_named(ctx, buffer(0)),
            island_rest: k.island_rest.bind_named(ctx, buffer(0)),
            fall_asleep: k.fall_asleep.bind_named(ctx, buffer(0)),
            key,
        };
        if self.groups.len() == PAIR_SETS {
            self.groups.remove(0);
        }
        self.groups.push(groups);
        self.groups.len() - 1
    }

    fn ensure_wake_group(&mut self, bodies: &wgpu::Buffer, shapes: &wgpu::Buffer) {
        let key = (self.pool.generation(), bodies.clone(), shapes.clone());
        if self.wake_group.as_ref().is_some_and(|(k, _)| *k == key) {
            return;
        }
        let k = self.pipelines.as_ref().expect("enabled");
        let group = k.wake_islands.bind_named(&self.ctx, |name| match name {
            "bodies" => bodies,
            "shapes" => shapes,
            name => self.pool.get(name),
        });
        self.wake_group = Some((key, group));
    }

    /// Records the start of a step: the islands of the bodies the host touched are flagged,
    /// then every flagged island wakes, its bodies restored in the solver's `bodies` and the
    /// collision `shapes`, and the flags clear. Nothing is recorded while the stage is off.
    pub fn record_wake(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut StageTimer,
        bodies: &wgpu::Buffer,
        shapes: &wgpu::Buffer,
    ) {
        if !self.is_enabled() || self.body_count == 0 {
            return;
        }
        self.ensure_wake_group(bodies, shapes);
        let k = self.pipelines.as_ref().expect("enabled");
        let (_, wake_group) = self.wake_group.as_ref().expect("built above");
        let queued = (!self.queued.is_empty()).then(|| {
            let buffer = self.ctx.storage_buffer("queued wakes", &self.queued);
            let group = k.wake_bodies.bind_named(&self.ctx, |name| match name {
                "queued" => &buffer,
                name => self.pool.get(name),
            });
            (buffer, group)
        });
        self.queued.clear();
        encoder.clear_buffer(self.pool.get(ACTIVE), 0, None);
        {
            let mut pass = timer.begin_pass(encoder, SLEEP_WAKE);
            if let Some((_, group)) = &queued {
                k.wake_bodies.dispatch_workgroups(&mut pass, group, 1, 1);
            }
            k.wake_islands
                .dispatch(&mut pass, wake_group, self.body_count);
        }
        encoder.clear_buffer(self.pool.get(WAKE), 0, None);
    }

    /// Records the end of a step, after the solver: rest times, the island search over the
    /// step's manifolds, each island's shortest rest, and the islands that fall asleep.
    /// Nothing is recorded while the stage is off.
    pub fn record_update(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut StageTimer,
        inputs: &StepBuffers<'_>,
    ) {
        if !self.is_enabled() || self.body_count == 0 {
            return;
        }
        let index = self.ensure_groups(inputs);
        let k = self.pipelines.as_ref().expect("enabled");
        let g = &self.groups[index];
        let n = self.body_count;
        let work = inputs.contact_work;
        encoder.clear_buffer(self.pool.get(UNFINISHED), 0, None);
        encoder.clear_buffer(self.pool.get(READY), 0, None);
        let search = self.pool.get(SEARCH_GROUPS);
        let mut pass = timer.begin_pass(encoder, SLEEP_ISLANDS);
        k.update_rest.dispatch(&mut pass, &g.update_rest, n);
        k.touch_sleepers
            .dispatch_work(&mut pass, &g.touch_sleepers, work);
        if self.kinematic_count > 0 {
            k.kinematic_wake.dispatch(&mut pass, &g.kinematic_wake, n);
        }
        k.plan_search
            .dispatch_workgroups(&mut pass, &g.plan_search, 1, 1);
        for round in 0..ISLAND_ROUNDS as usize {
            let side = round % 2;
            k.hook_labels.dispatch_indirect(
                &mut pass,
                &g.hook_labels[side],
                search,
                LINK_GROUPS_OFFSET,
            );
            k.jump_labels.dispatch_indirect(
                &mut pass,
                &g.jump_labels[side],
                search,
                BODY_GROUPS_OFFSET,
            );
        }
        k.check_labels
            .dispatch_indirect(&mut pass, &g.check_labels, search, LINK_GROUPS_OFFSET);
        k.island_rest
            .dispatch_indirect(&mut pass, &g.island_rest, search, BODY_GROUPS_OFFSET);
        k.fall_asleep
            .dispatch_indirect(&mut pass, &g.fall_asleep, search, BODY_GROUPS_OFFSET);
    }
}
