//! The color and solve stages on the GPU: buffers, bind groups, and the recording of one
//! step's solver work into a command encoder (no CPU read anywhere inside).

use wgpu::util::DeviceExt;

use crate::buffer_pool::{BufferPool, STORAGE_USAGE, UNIFORM_USAGE, bytes_of};
use crate::collision::StepBuffers;
use crate::kernel::Kernel;
use crate::kernels::radix_sort::{
    RadixBindGroups, RadixBuffers, RadixPass, RadixSort, index_bits, result_copy,
};
use crate::layout::DispatchArgs;
use crate::{GpuContext, GpuError, StageTimer};

use super::color::ColorGroups;
use super::constants::{
    COLOR_OFFSETS_LEN, COLOR_SLOTS, COLOR_TALLY_LEN, CONSTRAINT_ROWS, EMPTY_COLOR,
    GRAPH_COLOR_COUNT, TALLY_COUNTS,
};
use super::constraint_store::{constraints_by_manifold, store_stride};
use super::effects::{Effects, effect_overrides};
use super::layout::{ColorSlot, GpuConstraint, GpuSolverBody, GpuTilt, SolverParams};
use super::path::{FusedMemory, SolvePath, WarmStartSweep, WorldGrouping};
use super::pipelines::{SolverPipelines, pass_kernels, solve_step_kernel};
use super::solve_color::PassKind;
use super::solve_step::SubstepDispatch;

mod bind_groups;
mod substeps;
mod sweep;
mod worlds;

use sweep::PassGroups;

// Named as the kernels' bindings are (`bind_groups`), but for the copies kept per parity.
const SOLVER_BODIES: &str = "solver_bodies";
const CONSTRAINTS: &str = "constraints";
const COLOR_STATE: [&str; 2] = ["color_state_0", "color_state_1"];
const TILTS: [&str; 2] = ["tilts_0", "tilts_1"];
const COLOR_MARKS: &str = "color_marks";
const WORLD_FIRST: &str = "world_first";
const WORLD_END: &str = "world_end";
const WORLD_BODIES: &str = "world_bodies";
const COLOR_SCRATCH: &str = "color_scratch";
const COLOR_TALLY: &str = "color_tally";
const COLOR_OFFSETS: &str = "color_offsets";
const COLOR_ARGS: &str = "color_args";
const SORT_KEYS: [&str; 2] = ["color_sort_keys_0", "color_sort_keys_1"];
const SORT_VALUES: [&str; 2] = ["color_sort_values_0", "color_sort_values_1"];
const SORT_TILES: &str = "color_sort_tiles";
/// `solve_step`'s ticket and done counters and its fault word, cleared before each of its
/// dispatches.
const STEP_PROGRESS: &str = "step_progress";
/// The solver's buffers left out of checkpoints. Those that every step rewrites before
/// reading: the constraint store (prepare_contacts writes every slot a step visits), the
/// coloring's marks and undecided lists (the marks cleared at the start of each step), the
/// sort keys of the order by color; the largest is the constraint store, 368 bytes per pair
/// slot. And the colors and tilts kept per parity: a step writes only its own parity and
/// binds last step's read-only (`previous_colors`, `previous_tilts`), as the collision
/// stage's parity buffers (`crate::collision::buffers::PARITY_BUFFERS`).
const PER_STEP: [&str; 10] = [
    CONSTRAINTS,
    STEP_PROGRESS,
    COLOR_MARKS,
    COLOR_SCRATCH,
    SORT_KEYS[0],
    SORT_KEYS[1],
    COLOR_STATE[0],
    COLOR_STATE[1],
    TILTS[0],
    TILTS[1],
];
/// Bits of the color sort's keys: every color slot and `EMPTY_COLOR` (one past them).
const COLOR_SORT_BITS: u32 = index_bits(EMPTY_COLOR + 1);

/// What the solver stage is given by the caller: the step's buffers (the world's bodies and
/// the collision stage's contacts, or contacts the host wrote) and their sizes.
#[derive(Clone, Copy, Debug)]
pub struct SolverInputs<'a> {
    /// The step's buffers; poses and velocities are read and written, impulses written.
    pub buffers: StepBuffers<'a>,
    /// Bodies in the step.
    pub body_count: u32,
    /// Slots of the contact buffers: the most manifolds a step can have.
    pub contact_capacity: u32,
}

/// What the cached bind groups were made from.
#[derive(Clone, Debug, PartialEq, Eq)]
struct BindKey {
    generation: u64,
    inputs: [wgpu::Buffer; 6],
}

#[derive(Debug)]
struct BindGroups {
    color: [ColorGroups; 2],
    radix: RadixBindGroups,
    prepare_bodies: wgpu::BindGroup,
    prepare_contacts: [wgpu::BindGroup; 2],
    warm_start_bodies: wgpu::BindGroup,
    integrate_velocities: wgpu::BindGroup,
    integrate_positions: wgpu::BindGroup,
    finalize_bodies: wgpu::BindGroup,
    store_impulses: [wgpu::BindGroup; 2],
    /// `solve_color`'s, by [`PassKind::index`].
    passes: Vec<PassGroups>,
    solve_fused: [wgpu::BindGroup; 2],
    solve_fused_shared: [wgpu::BindGroup; 2],
    solve_worlds: [wgpu::BindGroup; 2],
    solve_worlds_shared: [wgpu::BindGroup; 2],
    /// `solve_step`'s, where the device has it.
    solve_step: Option<wgpu::BindGroup>,
}

/// The GPU solver stage: owns its pipelines (shared per device and effects), its buffers
/// (constraints, coloring state, per-step body state) and the bind groups over them.
#[derive(Debug)]
pub struct GpuSolver {
    ctx: GpuContext,
    effects: Effects,
    pipelines: SolverPipelines,
    /// `solve_color`, one per [`PassKind`] in [`PassKind::ALL`] order.
    passes: Vec<Kernel>,
    /// `solve_step`, on devices with `@coherent` storage.
    solve_step: Option<Kernel>,
    /// How the wide path dispatches its substeps ([`SubstepDispatch`]).
    substep_dispatch: SubstepDispatch,
    /// Whether the last recorded step ran its substeps in one dispatch.
    last_one_dispatch: bool,
    /// Graph colors each pass dispatches one by one; the tail takes the rest
    /// ([`Self::set_color_dispatches`]).
    color_dispatches: u32,
    /// Independent worlds in the step ([`Self::set_worlds`]).
    worlds: u32,
    /// The world count, each world's first body and the body count, then the groups of
    /// worlds (their count, each one's first world, the world count), for `solve_worlds`;
    /// written to its buffer by the next record.
    world_bodies: Option<Vec<u32>>,
    /// Groups of worlds [`SolvePath::Worlds`] runs, one workgroup each.
    world_groups: u32,
    /// Bodies of the largest group of worlds.
    max_group_bodies: u32,
    /// How [`SolvePath::Worlds`] packs the worlds into groups ([`WorldGrouping`]).
    world_grouping: WorldGrouping,
    /// How the wide path's warm start visits the graph colors ([`WarmStartSweep`]).
    warm_start: WarmStartSweep,
    radix: RadixSort,
    pool: BufferPool,
    params: wgpu::Buffer,
    last_params: Option<SolverParams>,
    /// The `ColorPass` uniforms of `solve_color` (none on a device with immediate data).
    pass_colors: Vec<wgpu::Buffer>,
    sort_passes: Vec<RadixPass>,
    parity: usize,
    /// The bind groups over the step buffers of the last two steps, the latest first
    /// ([`Self::rebind`]).
    bind: Vec<(BindKey, BindGroups)>,
    fused_memory: FusedMemory,
}

impl GpuSolver {
    /// A solver with `effects` compiled in.
    pub fn new(ctx: &GpuContext, effects: Effects) -> Result<Self, GpuError> {
        let effects = Effects {
            sleep: false,
            ..effects
        };
        let pipelines = SolverPipelines::new(ctx, &effects)?;
        let passes = pass_kernels(ctx, &effects)?;
        let substep_dispatch = SubstepDispatch::default();
        let solve_step = solve_step_kernel(
            ctx,
            &effects,
            substep_dispatch.may_use_one_dispatch(ctx.info.device_type),
        )?;
        let params = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("solver params"),
            size: std::mem::size_of::<SolverParams>() as u64,
            usage: UNIFORM_USAGE,
            mapped_at_creation: false,
        });
        // One color per slot, then the tails from each slot on (`PassGroups::Uniform`);
        // none where the color goes in as immediate data.
        let pass_colors = if ctx.has_immediates {
            Vec::new()
        } else {
            sweep::all_color_passes()
                .map(|pass| {
                    ctx.device
                        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                            label: Some("color pass"),
                            contents: bytemuck::bytes_of(&pass),
                            usage: wgpu::BufferUsages::UNIFORM,
                        })
                })
                .collect()
        };
        // Colors and EMPTY_COLOR fit in one digit of COLOR_SORT_BITS: the order by color is one
        // counting pass.
        let radix = RadixSort::with_digit_bits(ctx, COLOR_SORT_BITS)?;
        let sort_passes = radix.plan(&[(true, COLOR_SORT_BITS)]);
        Ok(Self {
            ctx: ctx.clone(),
            effects,
            pipelines,
            passes,
            solve_step,
            substep_dispatch,
            last_one_dispatch: false,
            color_dispatches: GRAPH_COLOR_COUNT,
            worlds: 1,
            world_bodies: None,
            world_groups: 0,
            max_group_bodies: 0,
            world_grouping: WorldGrouping::default(),
            warm_start: WarmStartSweep::default(),
            radix,
            pool: BufferPool::new(ctx).with_per_step(&PER_STEP),
            params,
            last_params: None,
            pass_colors,
            sort_passes,
            parity: 0,
            bind: Vec::with_capacity(2),
            fused_memory: FusedMemory::default(),
        })
    }

    /// Where the fused path keeps the bodies from the next step on ([`FusedMemory`]; both
    /// kernels compute the same bits).
    pub fn set_fused_memory(&mut self, memory: FusedMemory) {
        self.fused_memory = memory;
    }

    /// How many graph colors each pass of the wide path dispatches one by one, from the next
    /// step on (at most [`GRAPH_COLOR_COUNT`], the default). Every pass ends with one more
    /// dispatch, a single thread that visits the constraints of the colors from `colors` on
    /// in turn and then the overflow set. An empty color's dispatch still costs its launch and
    /// barrier (about 4 us on an H200), so the world sets this to the colors a recent step
    /// used; a color beyond it is still solved, by the tail (slowly, one constraint after
    /// another, until the next stats read raises the count). The bits never depend on it:
    /// each constraint is visited by the same code with the same inputs, in the same color
    /// order. Errs, changing nothing, on more colors than there are.
    pub fn set_color_dispatches(&mut self, colors: u32) -> Result<(), GpuError> {
        if colors > GRAPH_COLOR_COUNT {
            return Err(GpuError::InvalidInput {
                field: "color_dispatches".into(),
                value: format!("{colors} (expected at most {GRAPH_COLOR_COUNT})"),
            });
        }
        self.color_dispatches = colors;
        Ok(())
    }

    /// How the wide path's warm start visits the graph colors from the next step on
    /// ([`WarmStartSweep`]; the same bits either way).
    pub fn set_warm_start_sweep(&mut self, sweep: WarmStartSweep) {
        self.warm_start = sweep;
    }

    /// How the wide path's warm start visits the graph colors ([`Self::set_warm_start_sweep`]).
    pub fn warm_start_sweep(&self) -> WarmStartSweep {
        self.warm_start
    }

    /// Graph colors each wide pass dispatches one by one ([`Self::set_color_dispatches`]).
    pub fn color_dispatches(&self) -> u32 {
        self.color_dispatches
    }

    /// The per-color counts of the last recorded step (`COLOR_SLOTS` entries, the overflow
    /// set last), zeroed at the start of every step and written by the wide path's coloring.
    pub fn color_counts(&self) -> (&wgpu::Buffer, u64) {
        (
            self.pool.get(COLOR_TALLY),
            u64::from(TALLY_COUNTS) * std::mem::size_of::<u32>() as u64,
        )
    }

    /// Whether the next fused step of `bodies` bodies keeps them in workgroup memory.
    pub fn fused_in_workgroup(&self, bodies: u32) -> bool {
        self.fused_memory
            .in_workgroup(bodies, self.ctx.info.device_type)
    }

    /// The solver's pooled buffers (for saving and restoring a world's state).
    pub(crate) fn pool(&self) -> &BufferPool {
        &self.pool
    }

    /// The solver's pooled buffers, to write a saved state into.
    pub(crate) fn pool_mut(&mut self) -> &mut BufferPool {
        &mut self.pool
    }

    /// Which copy of the colors and tilts the next step writes (0 or 1).
    pub(crate) fn parity(&self) -> usize {
        self.parity
    }

    /// Sets the parity a saved world had (0 or 1).
    pub(crate) fn set_parity(&mut self, parity: usize) {
        self.parity = parity % 2;
    }

    /// The pipelines in use.
    pub fn pipelines(&self) -> &SolverPipelines {
        &self.pipelines
    }

    /// The effects compiled in.
    pub fn effects(&self) -> Effects {
        self.effects
    }

    /// Switches to pipelines with `effects` (bind groups are rebuilt on the next record).
    /// The sleep switch is not the solver's: it is dropped, so toggling it builds nothing.
    pub fn set_effects(&mut self, effects: Effects) -> Result<(), GpuError> {
        let effects = Effects {
            sleep: false,
            ..effects
        };
        if effect_overrides(&effects) != effect_overrides(&self.effects) {
            self.pipelines = SolverPipelines::new(&self.ctx, &effects)?;
            self.passes = pass_kernels(&self.ctx, &effects)?;
            self.solve_step = solve_step_kernel(
                &self.ctx,
                &effects,
                self.substep_dispatch
                    .may_use_one_dispatch(self.ctx.info.device_type),
            )?;
            self.bind.clear();
        }
        self.effects = effects;
        Ok(())
    }

    /// Forgets last step's colors, so the next step's coloring is not seeded (after the
    /// contact list was rebuilt on the host and `previous` indices no longer apply).
    pub fn forget_colors(&mut self) {
        self.parity = 0;
    }

    /// Grows the solver's buffers for `bodies` bodies and `capacity` contacts.
    fn ensure(&mut self, bodies: u32, capacity: u32) -> Result<(), GpuError> {
        let (n, cap) = (u64::from(bodies.max(1)), u64::from(capacity.max(1)));
        let sort_tiles = self.radix.tile_count_len(capacity.max(1));
        let sizes = [
            (TILTS[0], bytes_of::<GpuTilt>(cap)),
            (TILTS[1], bytes_of::<GpuTilt>(cap)),
            (SOLVER_BODIES, bytes_of::<GpuSolverBody>(n)),
            (CONSTRAINTS, bytes_of::<GpuConstraint>(cap)),
            (COLOR_STATE[0], bytes_of::<ColorSlot>(cap)),
            (COLOR_STATE[1], bytes_of::<ColorSlot>(cap)),
            // Per body its used-color mask, then one claim per (body, color).
            (
                COLOR_MARKS,
                bytes_of::<u32>(n * u64::from(1 + GRAPH_COLOR_COUNT)),
            ),
            (COLOR_SCRATCH, bytes_of::<u32>(2 * cap)),
            // Per world its first manifold and one past its last; worlds are numbered densely,
            // so fewer than bodies.
            (WORLD_FIRST, bytes_of::<u32>(n)),
            (WORLD_END, bytes_of::<u32>(n)),
            // The world count, each world's first body, the body count; the group count, each
            // group's first world, the world count.
            (WORLD_BODIES, bytes_of::<u32>(2 * n + 4)),
            (COLOR_TALLY, bytes_of::<u32>(u64::from(COLOR_TALLY_LEN))),
            (COLOR_OFFSETS, bytes_of::<u32>(u64::from(COLOR_OFFSETS_LEN))),
            (COLOR_ARGS, bytes_of::<DispatchArgs>(u64::from(COLOR_SLOTS))),
            (SORT_KEYS[0], bytes_of::<u32>(cap)),
            (SORT_KEYS[1], bytes_of::<u32>(cap)),
            (SORT_VALUES[0], bytes_of::<u32>(cap)),
            (SORT_VALUES[1], bytes_of::<u32>(cap)),
            (SORT_TILES, bytes_of::<u32>(sort_tiles)),
            (STEP_PROGRESS, bytes_of::<u32>(3)),
        ];
        self.pool.ensure_all(&sizes, STORAGE_USAGE)?;
        Ok(())
    }

    /// This step's coloring state (`array<ColorSlot>`) after the last recorded step.
    pub fn colors(&self) -> &wgpu::Buffer {
        self.pool.get(COLOR_STATE[1 - self.parity])
    }

    /// This step's tilt impulses (`array<GpuTilt>`) after the last recorded step.
    pub fn tilts(&self) -> &wgpu::Buffer {
        self.pool.get(TILTS[1 - self.parity])
    }

    /// Writes last step's tilt impulses for the next record (`(previous index, tilt)`), for
    /// manifolds made by the host; makes room for `capacity` manifolds first.
    pub fn write_previous_tilts(
        &mut self,
        bodies: u32,
        capacity: u32,
        tilts: &[(u32, GpuTilt)],
    ) -> Result<(), GpuError> {
        self.ensure(bodies, capacity)?;
        let buffer = self.pool.get(TILTS[1 - self.parity]);
        let stride = std::mem::size_of::<GpuTilt>() as u64;
        for (slot, tilt) in tilts {
            self.ctx.queue.write_buffer(
                buffer,
                u64::from(*slot) * stride,
                bytemuck::bytes_of(tilt),
            );
        }
        Ok(())
    }

    /// Constraint indices grouped by color (ascending color, ascending index within a color).
    pub fn color_order(&self) -> &wgpu::Buffer {
        self.pool.get(SORT_VALUES[result_copy(&self.sort_passes)])
    }

    /// `COLOR_OFFSETS_LEN` offsets into [`Self::color_order`], as tumble-solver's
    /// `Coloring::offsets`.
    pub fn color_offsets(&self) -> &wgpu::Buffer {
        self.pool.get(COLOR_OFFSETS)
    }

    /// The constraint store: the prepared constraints with their final impulses, as rows of
    /// 16 bytes by constraint slot (`shaders/solver/common/constraint_store.wgsl`); slot `s`
    /// holds manifold `color_order()[s]`. [`Self::read_constraints`] gives them by manifold.
    pub fn constraints(&self) -> &wgpu::Buffer {
        self.pool.get(CONSTRAINTS)
    }

    /// The first `count` manifolds' constraints after the last recorded step, by manifold
    /// index, read from the store and the order by color. Blocks. After a step undone by the
    /// world's motion check the store (left out of the checkpoint) still holds the undone
    /// step's constraints until the next step, so read them only after a step that stood.
    pub fn read_constraints(&self, count: u32) -> Result<Vec<GpuConstraint>, GpuError> {
        if count == 0 {
            return Ok(Vec::new());
        }
        let store = self.pool.get(CONSTRAINTS);
        let stride = store_stride(store.size());
        let order: Vec<u32> = self
            .ctx
            .read_buffer(self.color_order(), 0, u64::from(count))?;
        let rows = self
            .ctx
            .read_buffer(store, 0, stride * u64::from(CONSTRAINT_ROWS))?;
        constraints_by_manifold(&rows, stride, &order)
    }

    /// The per-step body state (`array<GpuSolverBody>`).
    pub fn solver_bodies(&self) -> &wgpu::Buffer {
        self.pool.get(SOLVER_BODIES)
    }

    /// Records one step of the color and solve stages (and the pose update of `finish`)
    /// into `encoder`, along `path`. Nothing is read back; the next record continues from
    /// the GPU state this one leaves (colors seed the next step's coloring).
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut StageTimer,
        inputs: &SolverInputs<'_>,
        params: &SolverParams,
        path: SolvePath,
    ) -> Result<(), GpuError> {
        self.ensure(inputs.body_count, inputs.contact_capacity)?;
        let n = inputs.body_count;
        let inputs = &inputs.buffers;
        if self.last_params != Some(*params) {
            // Through the encoder, not the queue, so steps recorded back to back each see
            // their own values.
            let staging = self
                .ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("solver params upload"),
                    contents: bytemuck::bytes_of(params),
                    usage: wgpu::BufferUsages::COPY_SRC,
                });
            encoder.copy_buffer_to_buffer(&staging, 0, &self.params, 0, staging.size());
            self.last_params = Some(*params);
        }
        self.rebind(inputs);
        encoder.clear_buffer(self.pool.get(COLOR_MARKS), 0, None);
        encoder.clear_buffer(self.pool.get(COLOR_TALLY), 0, None);
        let (_, groups) = self.bind.first().expect("bound above");
        let k = &self.pipelines;
        let p = self.parity;
        let mut one_dispatch = false;
        match path {
            SolvePath::Fused => {
                let mut pass = timer.begin_pass(encoder, "solve_fused");
                if self.fused_in_workgroup(n) {
                    k.solve_fused_shared.dispatch_workgroups(
                        &mut pass,
                        &groups.solve_fused_shared[p],
                        1,
                        1,
                    );
                } else {
                    k.solve_fused
                        .dispatch_workgroups(&mut pass, &groups.solve_fused[p], 1, 1);
                }
            }
            SolvePath::Worlds => {
                self.clear_world_ranges(encoder);
                let mut pass = timer.begin_pass(encoder, "solve_worlds");
                self.record_worlds(&mut pass, groups, inputs.contact_work);
            }
            SolvePath::Wide => {
                // The GPU starts on what the step recorded before the solver (wakes, impulses,
                // the collision stages) while the host records the coloring and the substeps.
                submit_so_far(&self.ctx, encoder);
                let work = inputs.contact_work;
                {
                    let mut pass = timer.begin_pass(encoder, "color");
                    groups.color[p].record(&mut pass, k, work, self.worlds);
                    self.radix.record(&mut pass, &groups.radix, work);
                }
                {
                    let mut pass = timer.begin_pass(encoder, "prepare");
                    k.prepare_bodies
                        .dispatch(&mut pass, &groups.prepare_bodies, n);
                    k.prepare_contacts
                        .dispatch_work(&mut pass, &groups.prepare_contacts[p], work);
                }
                one_dispatch = self.record_substeps(encoder, timer, groups, n, params);
                {
                    let mut pass = timer.begin_pass(encoder, "finish");
                    k.store_impulses
                        .dispatch_work(&mut pass, &groups.store_impulses[p], work);
                    k.finalize_bodies
                        .dispatch(&mut pass, &groups.finalize_bodies, n);
                }
            }
        }
        self.last_one_dispatch = one_dispatch;
        self.parity = 1 - self.parity;
        Ok(())
    }

    /// Puts the bind groups over `inputs` first in [`Self::bind`], building them only when
    /// neither of the last two steps' sets was over the same buffers. The collision stage
    /// hands the solver its two parities' buffers on alternate steps, so keeping one set
    /// rebuilt every bind group (over 200, one per pass and color) every step: on lavapipe
    /// that was a third of the host's time recording a step (docs/gpu-solver.md).
    fn rebind(&mut self, inputs: &StepBuffers<'_>) {
        let key = BindKey {
            generation: self.pool.generation(),
            inputs: [
                inputs.bodies.clone(),
                inputs.poses.clone(),
                inputs.velocities.clone(),
                inputs.manifolds.clone(),
                inputs.contacts.clone(),
                inputs.contact_work.clone(),
            ],
        };
        if let Some(found) = self.bind.iter().position(|(k, _)| *k == key) {
            self.bind[..=found].rotate_right(1);
            return;
        }
        let groups = self.make_bind_groups(inputs);
        // Groups over buffers the pool has since replaced are never used again.
        let generation = key.generation;
        self.bind.retain(|(k, _)| k.generation == generation);
        self.bind.truncate(1);
        self.bind.insert(0, (key, groups));
    }
}

/// Submits what `encoder` holds and gives it a fresh encoder for the rest of the step. The
/// queue runs command buffers in submission order, so the step computes exactly what one
/// submit would; the GPU only starts earlier.
fn submit_so_far(ctx: &GpuContext, encoder: &mut wgpu::CommandEncoder) {
    let recorded = std::mem::replace(encoder, ctx.encoder("tumble step (continued)"));
    ctx.queue.submit([recorded.finish()]);
}
