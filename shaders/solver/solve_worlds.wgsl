// requires: solver/common/fused_solve.wgsl solver/common/fused_bindings.wgsl solver/common/body_slot.wgsl
// solve_worlds: the fused path for a batch of worlds (GpuWorld::set_bodies_in_worlds): one
// workgroup per world runs that world's whole color-and-solve stage (fused_solve.wgsl) over its
// constraints and bodies, in one dispatch for all the worlds. A world's constraints touch only
// its own bodies, so the workgroups share nothing; each runs the functions solve_fused runs for
// the world alone, in the same order, and gets its bits. The per-color offsets live in
// workgroup memory, one set per world.

// Per world, its first manifold (world_starts.wgsl; 0 for a world without manifolds).
@group(0) @binding(9) var<storage, read> world_first: array<u32>;
// `array<GpuVelocity>`, updated.
@group(0) @binding(12) var<storage, read_write> velocities: array<GpuVelocity>;
@group(0) @binding(13) var<storage, read_write> solver_bodies: array<GpuSolverBody>;
// Per world, one past its last manifold (world_starts.wgsl; 0 for a world without manifolds).
@group(0) @binding(17) var<storage, read> world_end: array<u32>;
// The world count, then each world's first body and, last, the body count.
@group(0) @binding(18) var<storage, read> world_bodies: array<u32>;

// This workgroup's world's per-color offsets (absolute constraint slots).
var<workgroup> color_offsets: array<u32, GRAPH_COLOR_COUNT + 2u>;
// The world count, read once by thread 0 and published.
var<workgroup> world_count: u32;
// This thread's world's first constraint, for constraint_rank.
var<private> world_base: u32;

// Constraint i's index among its world's, as the world alone numbers it.
fn constraint_rank(i: u32) -> u32 {
    return i - world_base;
}

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
    // Dispatches past the per-dimension limit fold into y (crates/tumble-gpu/src/kernel.rs).
    let w = group.x + group.y * groups.x;
    if local == 0u {
        world_count = world_bodies[0];
    }
    if w >= workgroupUniformLoad(&world_count) {
        return;
    }
    world_base = world_first[w];
    let first_body = world_bodies[1u + w];
    fused_solve_range(
        local,
        world_base,
        world_end[w] - world_base,
        first_body,
        world_bodies[2u + w] - first_body,
    );
}
