//! The solver's WGSL files (under `shaders/solver/` and `shaders/common/solver_types.wgsl`),
//! the common-file lists its kernels compose, and the pipeline builder that hands them the
//! solver constants.

use crate::kernel::{Kernel, KernelSpec};
use crate::shader::{WgslFile, common, override_names, wgsl_file};
use crate::{GpuContext, GpuError};

use super::constants::solver_constants;

/// The structs shared with the host (`layout.rs` in this module).
pub const SOLVER_TYPES: WgslFile = wgsl_file!("common/solver_types.wgsl");
/// `override` declarations of [`super::constants`] and the effect switches.
pub const SOLVER_CONSTANTS: WgslFile = wgsl_file!("solver/common/solver_constants.wgsl");
/// Lock masks, world inertia, gyroscopic term, integration (pure functions).
pub const BODY_MATH: WgslFile = wgsl_file!("solver/common/body_math.wgsl");
/// Preparation and the warm-start, solve and restitution passes of one constraint.
pub const CONTACT_MATH: WgslFile = wgsl_file!("solver/common/contact_math.wgsl");
/// Load, pass, store of one constraint and its bodies.
pub const CONSTRAINT_ACCESS: WgslFile = wgsl_file!("solver/common/constraint_access.wgsl");
/// Proposal, resolution and withdrawal of one constraint's color in a round.
pub const COLORING: WgslFile = wgsl_file!("solver/common/coloring.wgsl");
/// Coloring rounds and per-color counts in a single workgroup.
pub const COLOR_WORKGROUP: WgslFile = wgsl_file!("solver/common/color_workgroup.wgsl");

/// Every shared solver file, for validation.
pub const ALL_COMMON: &[WgslFile] = &[
    SOLVER_TYPES,
    SOLVER_CONSTANTS,
    BODY_MATH,
    CONTACT_MATH,
    CONSTRAINT_ACCESS,
    COLORING,
    COLOR_WORKGROUP,
];

/// Common files of the per-body kernels.
pub const BODY_COMMON: &[WgslFile] = &[
    common::CONSTANTS,
    common::INDEXING,
    common::LAYOUT,
    common::QUAT,
    SOLVER_TYPES,
    SOLVER_CONSTANTS,
    BODY_MATH,
];

/// Common files of the per-contact kernels.
pub const CONTACT_COMMON: &[WgslFile] = &[
    common::CONSTANTS,
    common::INDEXING,
    common::LAYOUT,
    common::QUAT,
    SOLVER_TYPES,
    SOLVER_CONSTANTS,
    BODY_MATH,
    CONTACT_MATH,
];

/// Common files of the per-color pass kernel.
pub const PASS_COMMON: &[WgslFile] = &[
    common::CONSTANTS,
    common::INDEXING,
    common::LAYOUT,
    common::QUAT,
    SOLVER_TYPES,
    SOLVER_CONSTANTS,
    BODY_MATH,
    CONTACT_MATH,
    CONSTRAINT_ACCESS,
];

/// Common files of the wide coloring rounds.
pub const COLOR_COMMON: &[WgslFile] = &[
    common::CONSTANTS,
    common::INDEXING,
    common::LAYOUT,
    SOLVER_TYPES,
    SOLVER_CONSTANTS,
    COLORING,
];

/// Common files of the single-workgroup coloring finish.
pub const COLOR_FINISH_COMMON: &[WgslFile] = &[
    common::CONSTANTS,
    common::INDEXING,
    common::LAYOUT,
    SOLVER_TYPES,
    SOLVER_CONSTANTS,
    COLORING,
    COLOR_WORKGROUP,
];

/// Common files of the fused kernel: everything.
pub const FUSED_COMMON: &[WgslFile] = &[
    common::CONSTANTS,
    common::INDEXING,
    common::LAYOUT,
    common::QUAT,
    SOLVER_TYPES,
    SOLVER_CONSTANTS,
    BODY_MATH,
    CONTACT_MATH,
    CONSTRAINT_ACCESS,
    COLORING,
    COLOR_WORKGROUP,
];

/// The solver constants plus `extra`, kept to the names `spec`'s module declares (a pipeline
/// may only be given overrides its shader has).
pub fn solver_overrides(
    spec: &KernelSpec,
    extra: &[(&'static str, f64)],
) -> Result<Vec<(&'static str, f64)>, GpuError> {
    let module = spec.check()?;
    let declared = override_names(&module);
    let mut values: Vec<(&'static str, f64)> = solver_constants()
        .into_iter()
        .filter(|(name, _)| !extra.iter().any(|(e, _)| e == name))
        .chain(extra.iter().copied())
        .filter(|(name, _)| declared.iter().any(|d| d == name))
        .collect();
    values.sort_by(|a, b| a.0.cmp(b.0));
    Ok(values)
}

/// Builds `spec`'s pipeline with the solver constants and `extra` (effects, pass kind).
pub fn build_kernel(
    ctx: &GpuContext,
    spec: &'static KernelSpec,
    extra: &[(&'static str, f64)],
) -> Result<Kernel, GpuError> {
    Kernel::specialized(ctx, spec, &solver_overrides(spec, extra)?)
}
