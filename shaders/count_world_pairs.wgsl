// requires: common/indexing.wgsl common/layout.wgsl
// count_world_pairs: the first of the pair sort by world (a step of several worlds, none
// with more than 45 bodies, so none with more pairs than one workgroup's rank sort holds):
// one thread per pair of the step counts it for its world, the world of its first body (the
// two bodies of a pair share a world). Then scan_world_pairs turns the counts into each
// world's first slot, scatter_world_pairs moves every pair into its world's run and
// sort_world_pairs sorts each run in one workgroup: four dispatches in place of the radix
// sort's 30 over the whole list, with the radix sort's result, since the pairs in (a, b)
// order are each world's pairs in (a, b) order, one world after the other.

// The step's pair `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
// The pairs' first bodies, as the sweep appended them.
@group(0) @binding(1) var<storage, read> pair_a: array<u32>;
// `array<GpuShape>` (the body's world in its flags).
@group(0) @binding(2) var<storage, read> shapes: array<GpuShape>;
// Pairs per world; zero before the dispatch.
@group(0) @binding(3) var<storage, read_write> world_pair_counts: array<atomic<u32>>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let k = thread_index(thread);
    if k >= work.count {
        return;
    }
    let world = shapes[pair_a[k]].flags >> BODY_WORLD_SHIFT;
    atomicAdd(&world_pair_counts[world], 1u);
}
