//! `solve_fused`: the color and solve stages in one workgroup and one dispatch, for scenes
//! small enough that per-dispatch overhead dominates. It computes exactly what the wide path
//! computes (same functions, same order), so the choice between them never changes a result.
//! `solve_fused_shared` is the same stage with the bodies in workgroup memory, over the same
//! buffers (`shaders/solver/common/fused_solve.wgsl` is their common body).

use crate::kernel::KernelSpec;
use crate::shader::file;

/// Kernel: a single workgroup.
pub static SOLVE_FUSED: KernelSpec = KernelSpec::new(file("solver/solve_fused.wgsl"));

/// Kernel: [`SOLVE_FUSED`] with the bodies in workgroup memory, over the same buffers; the
/// shader names the two body buffers `velocity_buffer` and `solver_body_buffer` (its workgroup
/// copies take the names `velocities` and `solver_bodies`).
pub static SOLVE_FUSED_SHARED: KernelSpec = KernelSpec::new(file("solver/solve_fused_shared.wgsl"));

/// Kernel: one workgroup per group of consecutive worlds of a batch, each running
/// [`SOLVE_FUSED`]'s stage over its group's constraints and bodies
/// (`shaders/solver/solve_worlds.wgsl`; the groups: `path::world_groups`).
pub static SOLVE_WORLDS: KernelSpec = KernelSpec::new(file("solver/solve_worlds.wgsl"));

/// Threads of a [`SOLVE_WORLDS`] workgroup: one warp on NVIDIA GPUs. A batch's worlds are
/// small (a few dozen bodies and constraints), and a workgroup this size lets a GPU keep one
/// group of worlds on every workgroup slot at once and makes its many barriers (between colors and
/// passes) cheap: on an H200, 4,096 columns of 20 solved in 1.35 ms with 32 threads and in
/// 5.3 ms with the 256 of the other kernels, one world per workgroup. With the worlds packed
/// in groups, 64 threads over groups of 128 bodies were 11% faster than 32 over 64 at 4,096
/// and 16,384 columns and slower on smaller batches and on pyramids (docs/benchmarks.md, "What
/// bounds the worlds path"). `order_by_color` gives each color slot a thread, so it must
/// exceed `EMPTY_COLOR`.
pub const WORLDS_WORKGROUP_SIZE: u32 = 32;
const _: () = assert!(WORLDS_WORKGROUP_SIZE > super::constants::EMPTY_COLOR);

/// The override values [`SOLVE_WORLDS`] is built with besides the effects.
pub const WORLDS_OVERRIDES: [(&str, f64); 1] = [("WORKGROUP_SIZE", WORLDS_WORKGROUP_SIZE as f64)];

/// Kernel: [`SOLVE_WORLDS`] with each world's bodies in workgroup memory, for worlds of at most
/// [`WORLDS_SHARED_BODIES`] bodies (`shaders/solver/solve_worlds_shared.wgsl`).
pub static SOLVE_WORLDS_SHARED: KernelSpec =
    KernelSpec::new(file("solver/solve_worlds_shared.wgsl"));

/// Bodies of one group of worlds [`SOLVE_WORLDS_SHARED`] holds in workgroup memory: 128 bytes
/// each, 8 KiB per workgroup, so that a GPU keeps many groups resident at once.
pub const WORLDS_SHARED_BODIES: u32 = 64;

/// The override values [`SOLVE_WORLDS_SHARED`] is built with besides the effects.
pub const WORLDS_SHARED_OVERRIDES: [(&str, f64); 2] = [
    ("WORKGROUP_SIZE", WORLDS_WORKGROUP_SIZE as f64),
    ("FUSED_SHARED_BODIES", WORLDS_SHARED_BODIES as f64),
];

/// Bodies [`SOLVE_FUSED_SHARED`] holds in workgroup memory: 128 bytes each (a velocity and a
/// solver state), 14 KiB in all, within the 16 KiB of workgroup memory every WebGPU device
/// offers, with room for the coloring's own workgroup variables.
pub const FUSED_SHARED_BODIES: u32 = 112;
