// requires: solver/common/fused_solve.wgsl solver/common/fused_bindings.wgsl
// solve_worlds_shared: solve_worlds with each world's bodies' velocities and solver state in
// workgroup memory for the whole stage (worlds of at most FUSED_SHARED_BODIES bodies, as this
// kernel is specialized), so that the barriers between a world's colors and passes are
// workgroup barriers only: the constraint slots need none, each being visited by the same
// thread in every pass (fused_solve.wgsl). The same functions in the same order as
// solve_worlds and solve_fused: the same bits.

// Per world, its first manifold (world_starts.wgsl; 0 for a world without manifolds).
@group(0) @binding(9) var<storage, read> world_first: array<u32>;
@group(0) @binding(12) var<storage, read_write> velocity_buffer: array<GpuVelocity>;
@group(0) @binding(13) var<storage, read_write> solver_body_buffer: array<GpuSolverBody>;
// Per world, one past its last manifold (world_starts.wgsl; 0 for a world without manifolds).
@group(0) @binding(17) var<storage, read> world_end: array<u32>;
// The world count, then each world's first body and, last, the body count.
@group(0) @binding(18) var<storage, read> world_bodies: array<u32>;

override FUSED_SHARED_BODIES: u32;

// The names the shared solver functions use: this world's bodies, from its first.
var<workgroup> velocities: array<GpuVelocity, FUSED_SHARED_BODIES>;
var<workgroup> solver_bodies: array<GpuSolverBody, FUSED_SHARED_BODIES>;
// This workgroup's world's per-color offsets (absolute constraint slots).
var<workgroup> color_offsets: array<u32, GRAPH_COLOR_COUNT + 2u>;
// The world count, read once by thread 0 and published.
var<workgroup> world_count: u32;
// This thread's world's first constraint and first body.
var<private> world_base: u32;
var<private> world_first_body: u32;

// Constraint i's index among its world's, as the world alone numbers it.
fn constraint_rank(i: u32) -> u32 {
    return i - world_base;
}

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
    // Dispatches past the per-dimension limit fold into y (crates/tumble-gpu/src/kernel.rs).
    let w = group.x + group.y * groups.x;
    if local == 0u {
        world_count = world_bodies[0];
    }
    if w >= workgroupUniformLoad(&world_count) {
        return;
    }
    world_base = world_first[w];
    world_first_body = world_bodies[1u + w];
    fused_solve_range(
        local,
        world_base,
        world_end[w] - world_base,
        world_first_body,
        world_bodies[2u + w] - world_first_body,
    );
}
