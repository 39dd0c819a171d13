// requires: solver/common/fused_solve.wgsl solver/common/fused_bindings.wgsl
// The part of solve_worlds and solve_worlds_shared they share: the world ranges, the per-world
// color offsets and constraint numbering, and the workgroup's entry into fused_solve_range for
// its world. The including kernel declares the bodies' velocities and solver states (bindings
// 12 and 13), body_slot and the load, store and sync hooks of fused_solve.wgsl.

// Per world, its first manifold (world_starts.wgsl; 0 for a world without manifolds).
@group(0) @binding(9) var<storage, read> world_first: array<u32>;
// Per world, one past its last manifold (world_starts.wgsl; 0 for a world without manifolds).
@group(0) @binding(17) var<storage, read> world_end: array<u32>;
// The world count, then each world's first body and, last, the body count.
@group(0) @binding(18) var<storage, read> world_bodies: array<u32>;

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

// The whole color-and-solve stage of the world of workgroup `group` (of `groups`).
fn solve_world(group: vec3<u32>, groups: vec3<u32>, local: u32) {
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
