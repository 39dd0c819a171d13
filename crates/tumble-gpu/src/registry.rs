//! Everything the crate's shaders are made of, in one place, for the checks that need no GPU
//! (`tests/tests/gpu_layout.rs`): every kernel with the override values it is checked with,
//! every shared WGSL file, and every struct shared with the host. A new kernel is listed in
//! [`KERNELS`], or the layout test fails naming its file.

use crate::kernel::KernelSpec;
use crate::layout::{StructLayout, shared_struct_layouts};
use crate::shader::{ShaderSource, WgslFile};
use crate::solver::{Effects, effect_overrides};
use crate::{kernels, sleep, solver};

/// Every kernel of the crate: the collision stages, the solver, the sleep stage.
pub static KERNELS: &[&KernelSpec] = &[
    &kernels::update_aabbs::UPDATE_AABBS,
    &kernels::choose_axis::CHOOSE_AXIS,
    &kernels::write_sort_keys::WRITE_SORT_KEYS,
    &kernels::radix_sort::RADIX_HISTOGRAM,
    &kernels::radix_sort::RADIX_SCAN,
    &kernels::radix_sort::RADIX_SCATTER,
    &kernels::rank_sort::RANK_SORT,
    &kernels::gather_sweep_boxes::GATHER_SWEEP_BOXES,
    &kernels::sweep_pairs::SWEEP_PAIRS,
    &kernels::sweep_pairs::LONG_PAIRS,
    &kernels::plan_dispatch::PLAN_DISPATCH,
    &kernels::match_pairs::MATCH_PAIRS,
    &kernels::collide_cuboids::COLLIDE_CUBOIDS,
    &kernels::carry_impulses::CARRY_IMPULSES,
    &kernels::compact_touching::COUNT_TOUCHING,
    &kernels::compact_touching::SCAN_TOUCHING,
    &kernels::compact_touching::WRITE_TOUCHING,
    &kernels::compact_touching::SCATTER_IMPULSES,
    &kernels::contact_events::CONTACT_BEGINS,
    &kernels::contact_events::CONTACT_ENDS,
    &solver::apply_impulses::APPLY_IMPULSES,
    &solver::color::COLOR_PROPOSE,
    &solver::color::COLOR_RESOLVE,
    &solver::color::COLOR_WITHDRAW,
    &solver::color::COLOR_FINISH,
    &solver::color::COLOR_COUNT,
    &solver::color::COLOR_PLAN,
    &solver::prepare::PREPARE_BODIES,
    &solver::prepare::PREPARE_CONTACTS,
    &solver::integrate::INTEGRATE_VELOCITIES,
    &solver::integrate::INTEGRATE_POSITIONS,
    &solver::integrate::FINALIZE_BODIES,
    &solver::solve_color::SOLVE_COLOR,
    &solver::store::STORE_IMPULSES,
    &solver::fused::SOLVE_FUSED,
    &solver::fused::SOLVE_FUSED_SHARED,
    &sleep::wake::WAKE_BODIES,
    &sleep::wake::WAKE_ISLANDS,
    &sleep::rest::UPDATE_REST,
    &sleep::touch::TOUCH_SLEEPERS,
    &sleep::kinematic::KINEMATIC_WAKE,
    &sleep::plan_search::PLAN_SEARCH,
    &sleep::islands::HOOK_LABELS,
    &sleep::islands::JUMP_LABELS,
    &sleep::islands::CHECK_LABELS,
    &sleep::rest::ISLAND_REST,
    &sleep::rest::FALL_ASLEEP,
];

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
/// declares, all on, and `solve_color` as its biased pass. A shader that fails to parse gets
/// no values, and the check then reports the parse error.
pub fn all_kernels() -> Vec<RegisteredKernel> {
    let mut extra = effect_overrides(&Effects::ALL).to_vec();
    extra.push(("PASS", f64::from(solver::constants::PASS_SOLVE)));
    KERNELS
        .iter()
        .map(|&spec| RegisteredKernel {
            spec,
            overrides: spec.declared(&extra).unwrap_or_default(),
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
    layouts
}
