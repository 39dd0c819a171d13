// requires: common/layout.wgsl
// Where body b's velocity and solver state are in the including kernel's `velocities` and
// `solver_bodies`: at b itself, for every kernel that keeps them in their storage buffers (or,
// as solve_fused_shared, in workgroup memory for one world whose bodies start at 0).
// solve_worlds_shared keeps one world's in workgroup memory and defines its own.

fn body_slot(b: u32) -> u32 {
    return b;
}
