// requires: solver/common/fused_solve.wgsl solver/common/fused_bindings.wgsl
// The part of solve_worlds and solve_worlds_shared they share: the ranges of a workgroup's
// group of worlds, its per-color offsets, the constraint numbering within each world, and the
// workgroup's entry into fused_solve_range for its group. The including kernel declares the
// bodies' velocities and solver states (bindings 12 and 13), body_slot and the load, store and
// sync hooks of fused_solve.wgsl.

// Per world, its first manifold (world_starts.wgsl; 0 for a world without manifolds).
@group(0) @binding(9) var<storage, read> world_first: array<u32>;
// Per world, one past its last manifold (world_starts.wgsl; 0 for a world without manifolds).
@group(0) @binding(17) var<storage, read> world_end: array<u32>;
// The world count W, each world's first body, the body count; then the group count, each
// group's first world, and W (crates/tumble-gpu/src/solver/gpu_solver/worlds.rs).
@group(0) @binding(18) var<storage, read> world_bodies: array<u32>;

// This workgroup's per-color offsets (absolute constraint slots).
var<workgroup> color_offsets: array<u32, GRAPH_COLOR_COUNT + 2u>;
// The group count, read once by thread 0 and published.
var<workgroup> group_count: u32;
// This workgroup's first body.
var<private> world_first_body: u32;

// Constraint i's index among its world's, as the world alone numbers it (a world's
// constraints are one run: world_starts.wgsl).
fn constraint_rank(i: u32) -> u32 {
    return i - world_first[bodies[manifolds[i].body_a].world];
}

// The whole color-and-solve stage of the group of workgroup `group` (of `groups`): its worlds
// run as one, which changes no world's bits. They share no body, so a constraint's color
// depends only on its own world's constraints (each numbered within its world), and a color's
// constraints, of any world, are independent.
fn solve_world(group: vec3<u32>, groups: vec3<u32>, local: u32) {
    // Dispatches past the per-dimension limit fold into y (crates/tumble-gpu/src/kernel.rs).
    let g = group.x + group.y * groups.x;
    let groups_at = world_bodies[0] + 2u;
    if local == 0u {
        group_count = world_bodies[groups_at];
    }
    if g >= workgroupUniformLoad(&group_count) {
        return;
    }
    let first_world = world_bodies[groups_at + 1u + g];
    let end_world = world_bodies[groups_at + 2u + g];
    // The worlds' manifolds are consecutive runs; a world without any has first = end = 0.
    var first = 0xffffffffu;
    var end = 0u;
    for (var w = first_world; w < end_world; w++) {
        if world_end[w] > world_first[w] {
            first = min(first, world_first[w]);
            end = max(end, world_end[w]);
        }
    }
    first = min(first, end);
    world_first_body = world_bodies[1u + first_world];
    fused_solve_range(
        local,
        first,
        end - first,
        world_first_body,
        world_bodies[1u + end_world] - world_first_body,
    );
}
