//! `solve_step`: the wide path's substeps (integrate velocities, warm start, each color of each
//! solve and relax pass, integrate positions, restitution) in one dispatch, its phases handed
//! out to workgroups as chunks in order by a ticket counter (`shaders/solver/solve_step.wgsl`).
//! It visits every body and constraint with the per-color path's functions in the per-color
//! path's order, so the two give the same bits; the choice is about speed
//! ([`SubstepDispatch`]).

use crate::kernel::KernelSpec;
use crate::shader::file;

/// Kernel: any number of workgroups of [`SOLVE_STEP_WORKGROUP_SIZE`] threads; built only on
/// devices with `@coherent` storage ([`crate::GpuContext::has_coherent`]).
pub static SOLVE_STEP: KernelSpec = KernelSpec::new(file("solver/solve_step.wgsl"));

/// Threads of a [`SOLVE_STEP`] workgroup, which is also the constraints of one chunk of a
/// color: one warp on NVIDIA GPUs, for the reason the per-color passes use one
/// (`super::constants::COLOR_PASS_WORKGROUP_SIZE`): each thread's visit is a chain of
/// dependent loads, and small chunks spread a color over more of the GPU.
pub const SOLVE_STEP_WORKGROUP_SIZE: u32 = 32;

/// Polls after which one wait of [`SOLVE_STEP`] gives up (a guard against a bug hanging the
/// GPU, at well over a second of polling): the kernel then sets its fault word, which the
/// world reads with the step's stats and reports as an error
/// ([`crate::step::stats_ring::StepStats::substep_wait_gave_up`]).
pub const SOLVE_STEP_WAIT_LIMIT: u32 = 1 << 24;

/// Workgroups of a [`SOLVE_STEP`] dispatch on a GPU: two per SM of an H100 or H200 (132
/// SMs). A chunk of a large phase spreads over them (`items_per_thread` in the kernel), so
/// each workgroup takes one or two tickets of a large phase. Measured on an H100 (Vulkan, driver
/// 580.159.04, `dispatch_probe 12,24,50,100 1 wide in-use per-body per-color,one:66,...`,
/// 4 substeps, 1 iteration and 1 relax; the solve pass per step, the per-color dispatches in
/// brackets): pyramid of 12 1.261 / 1.240 / 1.253 / 1.253 / 1.307 ms at 66 / 132 / 264 / 528
/// / 1,056 workgroups (1.312), pyramid of 24 2.301 / 1.519 / 1.383 / 1.406 / 1.560 ms (1.509).
/// More than the device holds at once cost their launch only (one that starts after the last
/// ticket was handed out ends at once) and never hang the step (the kernel's comment says
/// why).
pub const SOLVE_STEP_GROUPS: u32 = 264;

/// Bodies up to which [`SubstepDispatch::Auto`] takes one dispatch on a GPU. A phase's chunks
/// are spread over [`SOLVE_STEP_GROUPS`] workgroups, each thread visiting its constraints one
/// after another, so a color of many thousand constraints runs on fewer threads than its own
/// dispatch gives it. Measured on the H100 above with 264 workgroups (solve pass per step,
/// per-color dispatches first): pyramids of 8 (205 bodies) 1.275 / 1.204-1.221 ms, 16 (1,497)
/// 1.392-1.395 / 1.299-1.304, 24 (4,901) 1.508-1.510 / 1.384-1.386, 32 (11,441) 1.811 /
/// 1.924, 40 (22,141) 2.064 / 3.499; the pyramid of 50 2.42 against 3.1 ms even with 1,056
/// workgroups. The bound lies between the last size that gains and the first that loses: it
/// was 8,192 then. Once each chunk loaded its constraint before its wait (060d5f8), the same
/// H100 gave (`dispatch_probe 32,40 1 wide in-use per-body per-color,one:264`, one run each):
/// pyramid of 32 1.838 / 1.757 ms (step wall 3.403 / 3.192 ms), pyramid of 40 2.056 / 3.239,
/// so the bound moved between the two.
pub const SOLVE_STEP_MAX_BODIES: u32 = 16_384;

/// Workgroups of a [`SOLVE_STEP`] dispatch on a CPU adapter: one. On lavapipe (Mesa 23,
/// LLVM 15) two or more workgroups of this kernel, one per host thread, gave poses that
/// differ from the per-color dispatches' and from run to run after a few to twenty steps of a
/// landing pile, even with every thread counting itself done and waiting on the counter with
/// a read-modify-write; one workgroup gives the per-color bits every time, as do any number
/// with `LP_NUM_THREADS=1`. Which of lavapipe's workgroup barriers or atomics fails to order
/// the workgroups' accesses was not found. On a GPU the kernel is checked against the
/// per-color path bit for bit with one, three and [`SOLVE_STEP_GROUPS`] workgroups
/// (`tests/tests/gpu_determinism.rs`), and its pose hashes on pyramids of 12 to 100 with 66 to
/// 1,056 workgroups equal the per-color path's (`dispatch_probe`).
pub const SOLVE_STEP_CPU_GROUPS: u32 = 1;

/// Workgroups a [`SOLVE_STEP`] dispatch launches on `device_type`: [`SOLVE_STEP_GROUPS`], or
/// [`SOLVE_STEP_CPU_GROUPS`] on CPU adapters.
pub fn solve_step_groups(device_type: wgpu::DeviceType) -> u32 {
    if device_type == wgpu::DeviceType::Cpu {
        SOLVE_STEP_CPU_GROUPS
    } else {
        SOLVE_STEP_GROUPS
    }
}

/// How the wide path dispatches its substeps. Both compute the same bits; the choice is about
/// speed and is fixed per device, never made from timing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SubstepDispatch {
    /// [`Self::OneDispatch`] on GPUs with `@coherent` storage for steps of at most
    /// [`SOLVE_STEP_MAX_BODIES`] bodies, [`Self::PerColor`] otherwise (on CPU adapters, whose
    /// software rasterizer gains nothing from fewer dispatches and whose tests keep the
    /// per-color path as the default they check).
    #[default]
    Auto,
    /// One dispatch per phase: per color and pass, per body stage.
    PerColor,
    /// Every substep in one [`SOLVE_STEP`] dispatch of `groups` workgroups (`None`: as
    /// [`solve_step_groups`] picks); on a device without `@coherent` storage, per color.
    OneDispatch {
        /// Workgroups launched on a GPU, 1 to `MAX_WORKGROUPS_PER_DIMENSION` (65,535; another
        /// value is an error where the dispatch is set); a CPU adapter always launches
        /// [`SOLVE_STEP_CPU_GROUPS`].
        groups: Option<u32>,
    },
}

impl SubstepDispatch {
    /// Whether a step on `device_type` may run its substeps in one dispatch (the kernel is
    /// built only then).
    pub fn may_use_one_dispatch(self, device_type: wgpu::DeviceType) -> bool {
        match self {
            SubstepDispatch::Auto => device_type != wgpu::DeviceType::Cpu,
            SubstepDispatch::PerColor => false,
            SubstepDispatch::OneDispatch { .. } => true,
        }
    }

    /// The workgroups of one [`SOLVE_STEP`] dispatch for `bodies` bodies, or `None` for the
    /// per-color dispatches, on a device of `device_type` that has (`coherent`) or lacks
    /// `@coherent` storage.
    pub fn one_dispatch_groups(
        self,
        bodies: u32,
        device_type: wgpu::DeviceType,
        coherent: bool,
    ) -> Option<u32> {
        if !coherent {
            return None;
        }
        match self {
            SubstepDispatch::Auto
                if device_type != wgpu::DeviceType::Cpu && bodies <= SOLVE_STEP_MAX_BODIES =>
            {
                Some(solve_step_groups(device_type))
            }
            SubstepDispatch::Auto | SubstepDispatch::PerColor => None,
            SubstepDispatch::OneDispatch { groups } => Some(match groups {
                Some(groups) if device_type != wgpu::DeviceType::Cpu => groups,
                _ => solve_step_groups(device_type),
            }),
        }
    }

    /// Errs on a forced workgroup count outside 1 to `MAX_WORKGROUPS_PER_DIMENSION`, naming
    /// `field` and the value.
    pub fn validate(self, field: &str) -> Result<(), crate::GpuError> {
        if let SubstepDispatch::OneDispatch {
            groups: Some(groups),
        } = self
            && !(1..=crate::constants::MAX_WORKGROUPS_PER_DIMENSION).contains(&groups)
        {
            return Err(crate::GpuError::InvalidInput {
                field: format!("{field}.groups"),
                value: format!(
                    "{groups} (expected 1 to {})",
                    crate::constants::MAX_WORKGROUPS_PER_DIMENSION
                ),
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_takes_one_dispatch_on_gpus_with_coherent_storage_for_small_steps_only() {
        let gpu = wgpu::DeviceType::DiscreteGpu;
        let cpu = wgpu::DeviceType::Cpu;
        let auto = SubstepDispatch::Auto;
        assert_eq!(
            auto.one_dispatch_groups(4_901, gpu, true),
            Some(SOLVE_STEP_GROUPS)
        );
        assert_eq!(
            auto.one_dispatch_groups(SOLVE_STEP_MAX_BODIES, gpu, true),
            Some(SOLVE_STEP_GROUPS)
        );
        assert_eq!(
            auto.one_dispatch_groups(SOLVE_STEP_MAX_BODIES + 1, gpu, true),
            None
        );
        assert_eq!(auto.one_dispatch_groups(4_901, cpu, true), None);
        assert_eq!(auto.one_dispatch_groups(4_901, gpu, false), None);
        assert_eq!(
            SubstepDispatch::PerColor.one_dispatch_groups(4_901, gpu, true),
            None
        );
        // Forced: any size, the count given on a GPU, one on a CPU adapter.
        let three = SubstepDispatch::OneDispatch { groups: Some(3) };
        assert_eq!(three.one_dispatch_groups(1_000_000, gpu, true), Some(3));
        assert_eq!(
            three.one_dispatch_groups(10, cpu, true),
            Some(SOLVE_STEP_CPU_GROUPS)
        );
        let picked = SubstepDispatch::OneDispatch { groups: None };
        assert_eq!(
            picked.one_dispatch_groups(1_000_000, gpu, true),
            Some(SOLVE_STEP_GROUPS)
        );
        assert_eq!(
            picked.one_dispatch_groups(10, cpu, true),
            Some(SOLVE_STEP_CPU_GROUPS)
        );
        assert_eq!(picked.one_dispatch_groups(10, cpu, false), None);
    }

    #[test]
    fn a_forced_workgroup_count_outside_the_dispatch_limit_is_an_error_naming_it() {
        for bad in [0, 65_536] {
            let dispatch = SubstepDispatch::OneDispatch { groups: Some(bad) };
            let message = dispatch
                .validate("substep_dispatch")
                .unwrap_err()
                .to_string();
            assert!(
                message.contains("substep_dispatch.groups") && message.contains(&bad.to_string()),
                "{message}"
            );
        }
        for good in [None, Some(1), Some(65_535)] {
            SubstepDispatch::OneDispatch { groups: good }
                .validate("substep_dispatch")
                .unwrap();
        }
        SubstepDispatch::Auto.validate("substep_dispatch").unwrap();
    }
}
