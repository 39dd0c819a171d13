//! Everything the crate's shaders are made of, in one place, for the checks that need no GPU
//! (`tests/tests/gpu_layout.rs`): every kernel with the override values it is checked with,
//! every shared WGSL file, and every struct shared with the host. A new kernel is a field of
//! a stage's pipelines (or listed in [`KERNELS`]), or the layout test fails naming its file.

use std::sync::LazyLock;

use crate::collision::kernels::CollisionKernels;
use crate::kernel::KernelSpec;
use crate::layout::{StructLayout, shared_struct_layouts};
use crate::shader::{ShaderSource, WgslFile};
use crate::solver::{Effects, effect_overrides};
use crate::{kernels, sleep, solver};

/// Every kernel of the crate: the pipeline sets of the collision stages, the solver and the
/// sleep stage, then the kernels built on their own.
pub static KERNELS: LazyLock<Vec<&'static KernelSpec>> = LazyLock::new(|| {
    let own: &[&KernelSpec] = &[
        &kernels::radix_sort::RADIX_HISTOGRAM,
        &kernels::radix_sort::RADIX_SCAN,
        &kernels::radix_sort::RADIX_SCATTER,
        &kernels::contact_events::CONTACT_BEGINS,
        &kernels::contact_events::CONTACT_ENDS,
        &kernels::contact_summary::CONTACT_SUMMARY,
        &solver::solve_color::SOLVE_COLOR,
        &solver::solve_color::SOLVE_COLOR_IMMEDIATE,
        &solver::solve_step::SOLVE_STEP,
        &kernels::cast_rays::CAST_RAYS,
        &kernels::check_motion::CHECK_MOTION,
    ];
    [
        CollisionKernels::SPECS,
        solver::pipelines::SolverPipelines::SPECS,
        sleep::pipelines::SleepPipelines::SPECS,
        own,
    ]
    .concat()
});

/// A kernel as the checks build it: its spec and the override values it needs beyond the
/// host constants (for instance one effect specialization).
#[derive(Clone, Debug)]
pub struct RegisteredKernel {
    /// The kernel.
    pub spec: &'static KernelSpec,
    /// Extra override values, by WGSL name.
    pub overrides: Vec<(&'static str, f64)>,
}

/// Every kernel with the override values the checks build it with: the effect switches it
/// declares, all on, `solve_color` as its biased pass, `solve_worlds` with its own
/// workgroup size, and `solve_step` with its wait for CPU adapters. A shader that fails to parse gets
/// no values, and the check then reports the parse error.
pub fn all_kernels() -> Vec<RegisteredKernel> {
    let mut extra = effect_overrides(&Effects::ALL).to_vec();
    extra.push(("PASS", f64::from(solver::constants::PASS_SOLVE)));
    KERNELS
        .iter()
        .map(|&spec| {
            let mut overrides = spec.declared(&extra).unwrap_or_default();
            if std::ptr::eq(spec, &solver::fused::SOLVE_WORLDS) {
                overrides.extend_from_slice(&solver::fused::WORLDS_OVERRIDES);
            }
            if std::ptr::eq(spec, &solver::fused::SOLVE_WORLDS_SHARED) {
                overrides.retain(|(n, _)| *n != "FUSED_SHARED_BODIES");
                overrides.extend_from_slice(&solver::fused::WORLDS_SHARED_OVERRIDES);
            }
            if std::ptr::eq(spec, &solver::solve_step::SOLVE_STEP) {
                // The wait that lavapipe needs (the GPU form is an atomic load).
                overrides.push(("SOLVE_STEP_PER_THREAD_SYNC", 1.0));
            }
            RegisteredKernel { spec, overrides }
        })
        .collect()
}

/// Every WGSL file that is not a kernel but is composed in front of one (what the kernels'
/// `// requires:` directives reach), sorted by path.
pub fn all_common_files() -> Vec<WgslFile> {
    let mut files: Vec<WgslFile> = KERNELS
        .iter()
        .filter_map(|spec| ShaderSource::of(spec.file).ok())
        .flat_map(|source| source.files)
        .filter(|file| !KERNELS.iter().any(|k| k.file.path == file.path))
        .collect();
    files.sort_by_key(|f| f.path);
    files.dedup();
    files
}

/// The WGSL files whose every struct has a host twin in [`all_struct_layouts`] (each parses
/// with the files it requires).
pub fn host_shared_files() -> Vec<WgslFile> {
    [
        "common/layout.wgsl",
        "common/solver_types.wgsl",
        "sleep/common/sleep_types.wgsl",
        "common/ray_types.wgsl",
    ]
    .into_iter()
    .map(crate::shader::file)
    .collect()
}

/// Every host struct shared with WGSL.
pub fn all_struct_layouts() -> Vec<StructLayout> {
    let mut layouts = shared_struct_layouts();
    layouts.extend(crate::solver::layout::solver_struct_layouts());
    layouts.extend(crate::sleep::layout::sleep_struct_layouts());
    layouts.extend(kernels::cast_rays::ray_struct_layouts());
    layouts
}
