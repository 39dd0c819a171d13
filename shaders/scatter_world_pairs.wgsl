// requires: common/indexing.wgsl common/layout.wgsl
// scatter_world_pairs: one thread per pair of the step moves it into its world's run of the
// scratch copy, at the world's first slot (scan_world_pairs) plus a count taken atomically.
// The order inside a run depends on which thread came first; sort_world_pairs then sorts
// each run, and since no two pairs are equal, the result does not depend on that order.

// The step's pair `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
@group(0) @binding(1) var<storage, read> pair_a: array<u32>;
@group(0) @binding(2) var<storage, read> pair_b: array<u32>;
// `array<GpuShape>` (the body's world in its flags).
@group(0) @binding(3) var<storage, read> shapes: array<GpuShape>;
// Each world's first pair slot (scan_world_pairs).
@group(0) @binding(4) var<storage, read> world_pair_starts: array<u32>;
// Pairs placed per world so far; zero before the dispatch (scan_world_pairs).
@group(0) @binding(5) var<storage, read_write> world_pair_counts: array<atomic<u32>>;
// The pairs by world, unsorted within a world.
@group(0) @binding(6) var<storage, read_write> scratch_a: array<u32>;
@group(0) @binding(7) var<storage, read_write> scratch_b: array<u32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let k = thread_index(thread);
    if k >= work.count {
        return;
    }
    let a = pair_a[k];
    let world = shapes[a].flags >> BODY_WORLD_SHIFT;
    let slot = world_pair_starts[world] + atomicAdd(&world_pair_counts[world], 1u);
    scratch_a[slot] = a;
    scratch_b[slot] = pair_b[k];
}
