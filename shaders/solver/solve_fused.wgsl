// requires: solver/common/fused_solve.wgsl solver/common/fused_bindings.wgsl solver/common/body_slot.wgsl
// solve_fused: the whole color-and-solve stage in one workgroup and one dispatch, for small
// scenes (solver/common/fused_solve.wgsl), with the bodies' velocities and solver state in
// their storage buffers.

// Per-color offsets.
@group(0) @binding(9) var<storage, read_write> color_offsets: array<u32>;

// Constraint i's index among its world's: this kernel steps one world only
// (crates/tumble-gpu/src/solver/path.rs), whose constraints are numbered from 0.
fn constraint_rank(i: u32) -> u32 {
    return i;
}

// `array<GpuVelocity>`, updated.
@group(0) @binding(12) var<storage, read_write> velocities: array<GpuVelocity>;
@group(0) @binding(13) var<storage, read_write> solver_bodies: array<GpuSolverBody>;

fn load_velocities(local: u32, n: u32) {}

fn store_bodies(local: u32, n: u32) {}

fn sync_bodies() {
    sync_workgroup();
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(@builtin(local_invocation_index) local: u32) {
    fused_solve(local);
}
