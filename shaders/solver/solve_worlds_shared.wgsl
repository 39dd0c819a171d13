// requires: solver/common/worlds_solve.wgsl
// solve_worlds_shared: solve_worlds with each group's bodies' velocities and solver state in
// workgroup memory for the whole stage (groups of at most FUSED_SHARED_BODIES bodies, as this
// kernel is specialized), so that the barriers between a world's colors and passes are
// workgroup barriers only: the constraint slots need none, each being visited by the same
// thread in every pass (fused_solve.wgsl). The same functions in the same order as
// solve_worlds and solve_fused: the same bits.

@group(0) @binding(12) var<storage, read_write> velocity_buffer: array<GpuVelocity>;
@group(0) @binding(13) var<storage, read_write> solver_body_buffer: array<GpuSolverBody>;

override FUSED_SHARED_BODIES: u32;

// The names the shared solver functions use: this group's bodies, from its first.
var<workgroup> velocities: array<GpuVelocity, FUSED_SHARED_BODIES>;
var<workgroup> solver_bodies: array<GpuSolverBody, FUSED_SHARED_BODIES>;

// Body b's place in the workgroup copies.
fn body_slot(b: u32) -> u32 {
    return b - world_first_body;
}

fn load_velocities(local: u32, n: u32) {
    for (var k = local; k < n; k += WORKGROUP_SIZE) {
        velocities[k] = velocity_buffer[world_first_body + k];
    }
    workgroupBarrier();
}

// Called after the last pose is written; each thread copies the bodies it finalized.
fn store_bodies(local: u32, n: u32) {
    for (var k = local; k < n; k += WORKGROUP_SIZE) {
        velocity_buffer[world_first_body + k] = velocities[k];
        solver_body_buffer[world_first_body + k] = solver_bodies[k];
    }
}

fn sync_bodies() {
    workgroupBarrier();
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    solve_world(group, groups, local);
}
