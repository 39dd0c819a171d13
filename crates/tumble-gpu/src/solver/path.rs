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
/// the worlds (each workgroup walks its group's colors and passes between barriers), the wide
/// path's with the dispatches. Measured on an H100 (Vulkan, `batch_table`, 4 substeps, the
/// solve stage's GPU time per step, groups of worlds packed): columns of 20 took 0.25 against
/// the wide path's 0.35 + 0.05 ms (solve + color) at 1,024 worlds (21,504 bodies), 0.84
/// against 0.72 + 0.08 ms at 4,096 (86,016 bodies; the whole step 1.48 against 1.75 ms), and
/// 2.94 against 2.05 ms at 16,384 (344,064 bodies; the step 5.17 against 4.96 ms); 1,024
/// pyramids of 4 (31,744 bodies) 2.69 against 3.12 ms per step. The bound sits between the
/// last two column batches, where the step times cross.
pub const WORLDS_MAX_TOTAL_BODIES: u32 = 131_072;

/// Bodies from which [`WorldGrouping::Auto`] packs a batch's worlds into groups: 128 full
/// groups' worth. A small batch leaves most of the GPU idle, and there one world per
/// workgroup spreads the work over more of it; a large one fills every multiprocessor either
/// way, and there the packed worlds fill each workgroup's lanes. Measured on an H100
/// (`batch_table`, one sitting, ms per step alone against packed): 64 columns of 20 (1,344
/// bodies) 0.364 against 0.382, 256 columns (5,376) 0.397 against 0.404, 256 pyramids of 4
/// (7,936) 1.168 against 1.240, 512 columns (10,752) 0.469 against 0.456, 1,024 columns
/// (21,504) 0.729 against 0.558; in another sitting 4,096 columns 2.03 against 1.48 and 1,024
/// pyramids of 4 3.42 against 2.69. The two cross between 7,936 and 10,752 bodies.
pub const WORLDS_PACK_MIN_BODIES: u32 = 128 * WORLD_GROUP_BODIES;

/// Bodies a group of worlds of [`SolvePath::Worlds`] holds at most (a world with more is a
/// group alone): the bodies' copies of `solve_worlds_shared` hold this many.
pub const WORLD_GROUP_BODIES: u32 = super::fused::WORLDS_SHARED_BODIES;

/// How [`SolvePath::Worlds`] gives a batch's worlds to its workgroups. Every choice computes
/// the same bits: the worlds of a group share no body, so each constraint is colored and
/// solved as in its world alone (`gpu_worlds` checks it); the choice is about speed, made from
/// the batch's body count, never from timing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum WorldGrouping {
    /// [`Self::Packed`] from [`WORLDS_PACK_MIN_BODIES`] bodies in the batch on, else
    /// [`Self::Alone`].
    #[default]
    Auto,
    /// One world per workgroup.
    Alone,
    /// Consecutive worlds share a workgroup up to [`WORLD_GROUP_BODIES`] bodies (three columns
    /// of 20 share one); a larger world is a group alone.
    Packed,
}

impl WorldGrouping {
    /// The most bodies a group holds in a batch of `batch_bodies` bodies (0: every world
    /// alone).
    pub fn group_bodies(self, batch_bodies: u32) -> u32 {
        let packed = match self {
            WorldGrouping::Auto => batch_bodies >= WORLDS_PACK_MIN_BODIES,
            WorldGrouping::Alone => false,
            WorldGrouping::Packed => true,
        };
        if packed { WORLD_GROUP_BODIES } else { 0 }
    }
}

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

/// Consecutive worlds packed into groups of at most `max_bodies` bodies, greedily in world
/// order (a larger world alone): the first world of each group. `starts` holds each world's
/// first body, then the body count. One workgroup runs a group as one world: its worlds share
/// no body, so each constraint is colored and solved as in its world alone, while the worlds
/// of a small batch fill the workgroup's lanes (a column of 20 has about 10 constraints per
/// color, a third of a 32-thread workgroup).
pub fn world_groups(starts: &[u32], max_bodies: u32) -> Vec<u32> {
    let mut groups = Vec::new();
    let mut group_first_body = 0;
    for (w, pair) in starts.windows(2).enumerate() {
        if groups.is_empty() || pair[1] - group_first_body > max_bodies {
            groups.push(w as u32);
            group_first_body = pair[0];
        }
    }
    groups
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

#[cfg(test)]
mod tests {
    use super::{WORLD_GROUP_BODIES, WORLDS_PACK_MIN_BODIES, WorldGrouping, world_groups};

    #[test]
    fn groups_take_consecutive_worlds_up_to_the_body_bound() {
        // Worlds of 21 bodies: three fill 63 of 64, a fourth would make 84.
        let starts: Vec<u32> = (0..=7).map(|w| 21 * w).collect();
        assert_eq!(world_groups(&starts, 64), vec![0, 3, 6]);
        // A bound of one body: every world alone (the one-world-per-workgroup layout).
        assert_eq!(world_groups(&starts, 1), (0..7).collect::<Vec<_>>());
        // A world over the bound is a group alone, and the packing resumes after it.
        let starts = [0, 10, 110, 120, 150, 164];
        assert_eq!(world_groups(&starts, 64), vec![0, 1, 2]);
        // Two worlds that exactly fill the bound share a group.
        assert_eq!(world_groups(&[0, 32, 64], 64), vec![0]);
        // One world, and no world at all.
        assert_eq!(world_groups(&[0, 5], 64), vec![0]);
        assert!(world_groups(&[0], 64).is_empty());
    }

    #[test]
    fn auto_packs_worlds_from_the_bound_on() {
        // Below the bound every world runs alone (a group bound of 0 bodies), from it on the
        // groups hold up to WORLD_GROUP_BODIES, as asked for explicitly.
        let auto = WorldGrouping::Auto;
        assert_eq!(auto.group_bodies(WORLDS_PACK_MIN_BODIES - 1), 0);
        assert_eq!(
            auto.group_bodies(WORLDS_PACK_MIN_BODIES),
            WORLD_GROUP_BODIES
        );
        assert_eq!(WorldGrouping::Alone.group_bodies(u32::MAX), 0);
        assert_eq!(WorldGrouping::Packed.group_bodies(1), WORLD_GROUP_BODIES);
        // A bound of 0 puts every world alone.
        assert_eq!(world_groups(&[0, 5, 9, 30], 0), vec![0, 1, 2]);
    }
}
