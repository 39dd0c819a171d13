//! Everything the crate's shaders are made of, in one place, for the checks that need no GPU
//! (`tests/tests/gpu_layout.rs`): every kernel with the override values it is built with,
//! every shared WGSL file, and every struct shared with the host. A stage that adds kernels,
//! WGSL files or shared structs lists them here, or the layout test fails naming them.

use crate::kernel::KernelSpec;
use crate::layout::{StructLayout, shared_struct_layouts};
use crate::shader::{WgslFile, common};

/// A kernel as the checks build it: its spec and the override values it needs beyond
/// [`crate::constants::shader_constants`] (for instance one effect specialization).
#[derive(Clone, Debug)]
pub struct RegisteredKernel {
    /// The kernel.
    pub spec: &'static KernelSpec,
    /// Extra override values, by WGSL name.
    pub overrides: Vec<(&'static str, f64)>,
}

/// Every kernel of the crate.
pub fn all_kernels() -> Vec<RegisteredKernel> {
    crate::kernels::all()
        .into_iter()
        .map(|spec| RegisteredKernel {
            spec,
            overrides: Vec::new(),
        })
        .chain(crate::solver::registered_kernels())
        .chain(crate::sleep::registered_kernels())
        .collect()
}

/// Every WGSL file that is not a kernel (composed in front of kernels).
pub fn all_common_files() -> Vec<WgslFile> {
    common::ALL
        .iter()
        .chain(crate::solver::shaders::ALL_COMMON)
        .chain(crate::sleep::shaders::ALL_COMMON)
        .copied()
        .collect()
}

/// The WGSL files whose every struct has a host twin in [`all_struct_layouts`], each with the
/// common files it needs in front to parse.
pub fn host_shared_files() -> Vec<(WgslFile, Vec<WgslFile>)> {
    vec![
        (common::LAYOUT, vec![common::CONSTANTS]),
        (crate::solver::shaders::SOLVER_TYPES, vec![common::LAYOUT]),
        (crate::sleep::shaders::SLEEP_TYPES, vec![]),
    ]
}

/// Every host struct shared with WGSL.
pub fn all_struct_layouts() -> Vec<StructLayout> {
    let mut layouts = shared_struct_layouts();
    layouts.extend(crate::solver::layout::solver_struct_layouts());
    layouts.extend(crate::sleep::layout::sleep_struct_layouts());
    layouts
}
