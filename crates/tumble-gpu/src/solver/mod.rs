//! The solver stages on the GPU: graph coloring, constraint preparation, the substep loop
//! (integrate velocities, warm start, solve and relax color by color, integrate positions),
//! restitution, impulse storage and the pose update, as wide kernels (one dispatch per color
//! and pass) or as one fused single-workgroup kernel for small scenes.
//!
//! The math mirrors tumble-solver step for step; each kernel has a CPU twin (tumble-solver's
//! own function, or [`color::color_rounds_cpu`] for the coloring).

pub mod apply_impulses;
pub mod color;
pub mod constants;
pub mod convert;
pub mod effects;
pub mod fused;
pub mod gpu_solver;
pub mod integrate;
pub mod layout;
pub mod params;
pub mod path;
pub mod pipelines;
pub mod prepare;
pub mod shaders;
pub mod solve_color;
pub mod store;

use crate::kernel::KernelSpec;

pub use effects::Effects;
pub use gpu_solver::{GpuSolver, SolverInputs};
pub use params::StepParams;
pub use path::SolvePath;

/// Every solver kernel spec, for validation.
pub fn kernels() -> Vec<&'static KernelSpec> {
    vec![
        &apply_impulses::APPLY_IMPULSES,
        &color::COLOR_PROPOSE,
        &color::COLOR_RESOLVE,
        &color::COLOR_FINISH,
        &prepare::PREPARE_BODIES,
        &prepare::PREPARE_CONTACTS,
        &integrate::INTEGRATE_VELOCITIES,
        &integrate::INTEGRATE_POSITIONS,
        &integrate::FINALIZE_BODIES,
        &solve_color::SOLVE_COLOR,
        &store::STORE_IMPULSES,
        &fused::SOLVE_FUSED,
    ]
}

/// Every solver kernel with the override values the shader checks build it with (all effects
/// on; `solve_color` as its biased pass). A shader that fails to parse gets no values, and
/// the check then reports the parse error.
pub fn registered_kernels() -> Vec<crate::registry::RegisteredKernel> {
    let mut extra = Effects::ALL.overrides().to_vec();
    extra.push(("PASS", f64::from(constants::PASS_SOLVE)));
    kernels()
        .into_iter()
        .map(|spec| crate::registry::RegisteredKernel {
            spec,
            overrides: shaders::solver_overrides(spec, &extra).unwrap_or_default(),
        })
        .collect()
}
