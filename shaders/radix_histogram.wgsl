// requires: common/indexing.wgsl common/layout.wgsl
// radix_histogram: one workgroup per tile of WORKGROUP_SIZE keys counts the keys per digit
// of this pass and stores the counts digit-major (counts[digit * tiles + tile]), so that one
// exclusive scan over the array yields each tile's first output slot for each digit.

// This pass's RadixPassParams.
@group(0) @binding(0) var<uniform> pass_params: RadixPassParams;
// The `WorkList` giving the item count.
@group(0) @binding(1) var<storage, read> work: WorkList;
// Keys.
@group(0) @binding(2) var<storage, read> keys: array<u32>;
// Output counts, `RADIX * tiles` entries, digit-major.
@group(0) @binding(3) var<storage, read_write> tile_counts: array<u32>;

var<workgroup> counts: array<atomic<u32>, RADIX>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    // Counts start at zero: every workgroup's memory is zero-initialized (the pipelines are
    // built with zero_initialize_workgroup_memory).
    let tile = thread_group(thread);
    let tiles = (work.count + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    let i = tile * WORKGROUP_SIZE + thread.local;
    if tile < tiles && i < work.count {
        let digit = (keys[i] >> pass_params.shift) & (RADIX - 1u);
        atomicAdd(&counts[digit], 1u);
    }
    workgroupBarrier();
    if tile < tiles && thread.local < RADIX {
        tile_counts[thread.local * tiles + tile] = atomicLoad(&counts[thread.local]);
    }
}
