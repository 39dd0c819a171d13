// requires: common/layout.wgsl common/rank_sort.wgsl
// sort_world_pairs: one workgroup per world rank-sorts the world's run of pairs from the
// scratch copy (scatter_world_pairs) by (a, b) into the same slots of the pair list
// (common/rank_sort.wgsl). The runs follow each other in world order and a world's bodies
// are one run of indices, so the list ends in (a, b) order: the radix sort's result.

// Each world's first pair slot, then the pair count (scan_world_pairs).
@group(0) @binding(0) var<storage, read> world_pair_starts: array<u32>;
@group(0) @binding(1) var<storage, read> scratch_a: array<u32>;
@group(0) @binding(2) var<storage, read> scratch_b: array<u32>;
// The sorted pairs.
@group(0) @binding(3) var<storage, read_write> pair_a: array<u32>;
@group(0) @binding(4) var<storage, read_write> pair_b: array<u32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let first = world_pair_starts[group.x];
    let count = min(world_pair_starts[group.x + 1u] - first, RANK_SORT_ITEMS * WORKGROUP_SIZE);
    for (var i = local; i < count; i += WORKGROUP_SIZE) {
        shared_keys[i] = scratch_a[first + i];
        shared_values[i] = scratch_b[first + i];
    }
    workgroupBarrier();
    for (var i = local; i < count; i += WORKGROUP_SIZE) {
        let slot = rank_slot(i, count);
        pair_a[first + slot] = shared_keys[i];
        pair_b[first + slot] = shared_values[i];
    }
}
