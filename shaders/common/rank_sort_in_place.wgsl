// requires: common/rank_sort.wgsl
// The rank sort (common/rank_sort.wgsl) of `keys[first..first + n]` and the `values` beside
// them, in place; the including kernel declares both storage arrays. Call from uniform
// control flow (one workgroup barrier).

fn rank_sort_range(first: u32, n: u32, local: u32) {
    for (var i = local; i < n; i += WORKGROUP_SIZE) {
        shared_keys[i] = keys[first + i];
        shared_values[i] = values[first + i];
    }
    workgroupBarrier();
    for (var i = local; i < n; i += WORKGROUP_SIZE) {
        let slot = rank_slot(i, n);
        keys[first + slot] = shared_keys[i];
        values[first + slot] = shared_values[i];
    }
}
