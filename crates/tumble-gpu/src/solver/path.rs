//! Which of the two solver paths runs a step: the wide path (one dispatch per color and pass,
//! every thread of the GPU) or the fused path (one workgroup, one dispatch). Both compute the
//! same result; the choice is only about speed.

/// The fused path is used up to this many manifolds. One workgroup visits a color in
/// batches of `WORKGROUP_SIZE` constraints, so its cost grows with the manifold count, while
/// the wide path pays a nearly fixed cost per dispatch (about 80 per substep). Measured on an
/// H200 (Vulkan, `benches/src/bin/dispatch_probe.rs`, 4 substeps, the solver stages' GPU time
/// per step): fused 0.87 ms at 140 manifolds and 2.45 ms at 1,240, against a wide path of
/// 1.3 to 1.7 ms from 140 to 4,324 manifolds since its per-color passes run in one-warp
/// workgroups (it was 5 ms at 4,324 before, when this bound was 4,096). The two cross near
/// 600 manifolds.
pub const FUSED_MAX_CONSTRAINTS: u32 = 600;

/// A batch of worlds takes [`SolvePath::Worlds`] while its largest world has at most this
/// many bodies (a world's stage then runs in one workgroup, as the fused path's does for a
/// world of about this size: the column of 20 has 21) and the batch at most
/// [`WORLDS_MAX_TOTAL_BODIES`], and the wide path otherwise.
pub const WORLDS_MAX_BODIES: u32 = 128;

/// Bodies up to which a batch of small worlds takes [`SolvePath::Worlds`]. Its cost grows with
/// the worlds (each workgroup walks its world's colors and passes between barriers), the wide
/// path's with the dispatches: on an H200 (`batch_table`, solve stage GPU time) columns of 20
/// took 0.17 against 0.29 ms at 64 worlds, 0.36 against 0.35 ms at 1,024 (21,504 bodies),
/// 1.35 against 0.64 ms at 4,096, and 1,024 pyramids of 4 (31,744 bodies) 1.93 against
/// 1.56 ms. Those figures are for one world per workgroup; since a workgroup runs a group of
/// worlds (three columns of 20 share one), this bound is still the measured one, to be moved
/// where a GPU measures the two paths cross again.
pub const WORLDS_MAX_TOTAL_BODIES: u32 = 16_384;

/// The fused path is used up to this many bodies: its per-body stages also run in one
/// workgroup, `WORKGROUP_SIZE` bodies at a time (a pile at the manifold bound above has
/// about 90 bodies, so this bound only matters for sparse scenes).
pub const FUSED_MAX_BODIES: u32 = 4096;

/// How the color and solve stages are dispatched.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SolvePath {
    /// One dispatch per stage, color and pass, each as wide as its work.
    Wide,
    /// One single-workgroup dispatch for the whole color and solve stages.
    Fused,
    /// A batch of worlds: one dispatch with one workgroup per group of consecutive worlds
    /// (as many as fit in 64 bodies; a larger world alone), each running the fused stage over
    /// its group.
    Worlds,
}

impl SolvePath {
    /// The path for a step with `bodies` bodies and about `constraints` manifolds.
    pub fn choose(bodies: u32, constraints: u32) -> Self {
        if bodies <= FUSED_MAX_BODIES && constraints <= FUSED_MAX_CONSTRAINTS {
            SolvePath::Fused
        } else {
            SolvePath::Wide
        }
    }
}

/// Where the fused path keeps the bodies' velocities and solver state during its stage.
/// Both kernels run the same functions in the same order and compute the same bits; the
/// choice is about speed and is fixed per device, never made from timing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FusedMemory {
    /// Workgroup memory on GPUs, storage on CPU adapters (lavapipe runs the workgroup-memory
    /// kernel about ten times slower; an H200 runs it 18% faster on a pyramid of 4).
    #[default]
    Auto,
    /// Always in their storage buffers (`solve_fused`).
    Storage,
    /// In workgroup memory (`solve_fused_shared`) whenever the bodies fit
    /// ([`super::fused::FUSED_SHARED_BODIES`]), else in storage.
    Workgroup,
}

impl FusedMemory {
    /// Whether a fused step of `bodies` bodies on `device_type` keeps them in workgroup memory.
    pub fn in_workgroup(self, bodies: u32, device_type: wgpu::DeviceType) -> bool {
        let wanted = match self {
            FusedMemory::Auto => device_type != wgpu::DeviceType::Cpu,
            FusedMemory::Storage => false,
            FusedMemory::Workgroup => true,
        };
        wanted && bodies <= super::fused::FUSED_SHARED_BODIES
    }
}

/// How the wide path applies the warm start of the graph colors each substep. Both compute the
/// same bits (`warm_start_bodies.wgsl` says why); the choice is about speed and is fixed per
/// device, never made from timing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum WarmStartSweep {
    /// [`Self::PerBody`] on GPUs, [`Self::ByColor`] on CPU adapters: lavapipe runs the
    /// per-body kernel slower than the per-color dispatches (a pyramid of 12's solve took 295
    /// against 204 ms), since each constraint is loaded by both of its bodies' threads and a
    /// body's constraints one after another, while a GPU saves the launch and barrier of
    /// each color's dispatch.
    #[default]
    Auto,
    /// One dispatch, one thread per body walking its constraints in color order (one
    /// dispatch per substep instead of one per color).
    PerBody,
    /// One dispatch per color, one thread per constraint, as the other passes.
    ByColor,
}

impl WarmStartSweep {
    /// Whether the warm start on `device_type` runs per body.
    pub fn per_body(self, device_type: wgpu::DeviceType) -> bool {
        match self {
            WarmStartSweep::Auto => device_type != wgpu::DeviceType::Cpu,
            WarmStartSweep::PerBody => true,
            WarmStartSweep::ByColor => false,
        }
    }
}
