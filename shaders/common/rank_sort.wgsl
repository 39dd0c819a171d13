// requires: common/layout.wgsl
// The rank sort of one short list by one workgroup, shared by rank_sort (the whole list),
// sort_world_bodies (one world's bodies per workgroup) and sort_world_pairs (one world's
// pairs). The kernel copies the list's (key, value) pairs into `shared_keys` and
// `shared_values` (at most RANK_SORT_ITEMS * WORKGROUP_SIZE of them), waits at a workgroup
// barrier, and writes each item to the slot `rank_slot` gives it: the number of items ordered
// before it by key, then value, equal pairs in their input order.

// Items per thread; the host uses these kernels only for lists of at most
// RANK_SORT_ITEMS * WORKGROUP_SIZE items (tumble-gpu's RANK_SORT_CAPACITY).
override RANK_SORT_ITEMS: u32;

var<workgroup> shared_keys: array<u32, RANK_SORT_ITEMS * WORKGROUP_SIZE>;
var<workgroup> shared_values: array<u32, RANK_SORT_ITEMS * WORKGROUP_SIZE>;

// The sorted position of item `i` of the `n` items in workgroup memory.
fn rank_slot(i: u32, n: u32) -> u32 {
    let key = shared_keys[i];
    let value = shared_values[i];
    var slot = 0u;
    for (var j = 0u; j < n; j++) {
        let other = shared_keys[j];
        let other_value = shared_values[j];
        let same_key = other == key;
        let before = other < key || (same_key && other_value < value)
            || (same_key && other_value == value && j < i);
        slot += select(0u, 1u, before);
    }
    return slot;
}
