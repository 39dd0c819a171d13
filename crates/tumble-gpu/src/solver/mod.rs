//! The solver stages on the GPU: graph coloring, constraint preparation, the substep loop
//! (integrate velocities, warm start, solve and relax color by color, integrate positions),
//! restitution, impulse storage and the pose update, as wide kernels (one dispatch per color
//! and pass) or as one fused single-workgroup kernel for small scenes.
//!
//! The math mirrors tumble-solver step for step; each kernel has a CPU twin (tumble-solver's
//! own function, `tumble_solver::color_in_rounds` for the coloring).

pub mod apply_impulses;
pub mod color;
pub mod constants;
pub mod constraint_store;
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
pub mod solve_color;
pub mod solve_step;
pub mod store;

pub use effects::{Effects, effect_overrides};
pub use gpu_solver::{GpuSolver, SolverInputs};
pub use params::StepParams;
pub use path::{FusedMemory, SolvePath, WarmStartSweep, WorldGrouping};
pub use solve_step::SubstepDispatch;
