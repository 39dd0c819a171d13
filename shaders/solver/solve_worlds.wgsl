// requires: solver/common/worlds_solve.wgsl solver/common/body_slot.wgsl
// solve_worlds: the fused path for a batch of worlds (GpuWorld::set_bodies_in_worlds): one
// workgroup per group of consecutive worlds runs their whole color-and-solve stage
// (fused_solve.wgsl) over the group's constraints and bodies, in one dispatch for all the
// worlds, with the bodies in their storage buffers. A world's constraints touch only its own
// bodies, so the workgroups share nothing, and within a group each world's constraints are
// colored and solved by the functions solve_fused runs for the world alone, in the same order:
// each world gets its bits. The per-color offsets live in workgroup memory, one set per group
// (worlds_solve.wgsl).

// `array<GpuVelocity>`, updated.
@group(0) @binding(12) var<storage, read_write> velocities: array<GpuVelocity>;
@group(0) @binding(13) var<storage, read_write> solver_bodies: array<GpuSolverBody>;

fn load_velocities(local: u32, n: u32) {}

fn store_bodies(local: u32, n: u32) {}

fn sync_bodies() {
    sync_workgroup();
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    solve_world(group, groups, local);
}
