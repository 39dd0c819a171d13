// requires: common/indexing.wgsl common/solver_types.wgsl
// world_starts: one thread per manifold of a step that holds several worlds writes, for the
// first manifold of each world, its index into world_first, from which the coloring numbers
// each world's constraints (color_bindings.wgsl's constraint_rank), and for the last one past
// its index into world_end (solve_worlds.wgsl's ranges). The manifolds are sorted by body pair
// and each world's bodies are one run, so each world's manifolds are one run; exactly one
// thread writes each entry. A world without manifolds keeps the entries the host cleared (0).

// The contacts' `WorkList`.
@group(0) @binding(0) var<storage, read> contact_work: WorkList;
@group(0) @binding(1) var<storage, read> manifolds: array<GpuManifold>;
@group(0) @binding(2) var<storage, read> bodies: array<GpuBody>;
// Output: per world, its first manifold's index.
@group(0) @binding(3) var<storage, read_write> world_first: array<u32>;
// Output: per world, one past its last manifold's index.
@group(0) @binding(4) var<storage, read_write> world_end: array<u32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= contact_work.count {
        return;
    }
    let world = bodies[manifolds[i].body_a].world;
    if i == 0u || bodies[manifolds[i - 1u].body_a].world != world {
        world_first[world] = i;
    }
    if i + 1u == contact_work.count || bodies[manifolds[i + 1u].body_a].world != world {
        world_end[world] = i + 1u;
    }
}
