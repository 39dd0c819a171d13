//! The sleep stage's WGSL files (under `shaders/sleep/`), the common files its kernels
//! compose, and the pipeline builder that hands them the sleep and solver constants.

use crate::kernel::{Kernel, KernelSpec};
use crate::shader::{WgslFile, common, wgsl_file};
use crate::solver::shaders::{SOLVER_CONSTANTS, SOLVER_TYPES, build_kernel, solver_overrides};
use crate::{GpuContext, GpuError};

use super::constants::sleep_constants;

/// The structs shared with the host (`layout.rs` in this module).
pub const SLEEP_TYPES: WgslFile = wgsl_file!("sleep/common/sleep_types.wgsl");
/// `override` declarations of [`super::constants`] and the linkable test.
pub const SLEEP_CONSTANTS: WgslFile = wgsl_file!("sleep/common/sleep_constants.wgsl");

/// Every shared sleep file, for validation.
pub const ALL_COMMON: &[WgslFile] = &[SLEEP_TYPES, SLEEP_CONSTANTS];

/// Common files of every sleep kernel: the collision layouts (poses, velocities, shapes,
/// manifolds), the solver's body struct and kind codes, and the sleep files.
pub const SLEEP_COMMON: &[WgslFile] = &[
    common::CONSTANTS,
    common::INDEXING,
    common::LAYOUT,
    SOLVER_TYPES,
    SOLVER_CONSTANTS,
    SLEEP_TYPES,
    SLEEP_CONSTANTS,
];

/// The override values `spec` is built with: the solver's constants (body kinds) and the
/// sleep constants it declares.
pub fn sleep_overrides(spec: &KernelSpec) -> Result<Vec<(&'static str, f64)>, GpuError> {
    solver_overrides(spec, &sleep_constants())
}

/// Builds `spec`'s pipeline with the shared, solver and sleep constants.
pub fn build_sleep_kernel(ctx: &GpuContext, spec: &'static KernelSpec) -> Result<Kernel, GpuError> {
    build_kernel(ctx, spec, &sleep_constants())
}
