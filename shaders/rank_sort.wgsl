// requires: common/layout.wgsl common/rank_sort_in_place.wgsl
// rank_sort: sorts up to RANK_SORT_ITEMS * WORKGROUP_SIZE (key, value) pairs in place by key,
// then value, equal pairs keeping their order, in one workgroup and one dispatch: for lists
// so short that the radix sort's passes (three dispatches per 4-bit digit) cost far more than
// their work (common/rank_sort.wgsl). Both uses give the radix sort's result bit for bit: the
// bodies' values are their input positions, so (key, value) order is the stable order by
// key; the pairs (a, b) are sorted by b and then stably by a, which is (a, b) order.

// The `WorkList` giving the item count (at most RANK_SORT_CAPACITY).
@group(0) @binding(0) var<storage, read> work: WorkList;
// Keys, sorted in place.
@group(0) @binding(1) var<storage, read_write> keys: array<u32>;
// Values, moved with their keys.
@group(0) @binding(2) var<storage, read_write> values: array<u32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(@builtin(local_invocation_index) local: u32) {
    rank_sort_range(0u, min(work.count, RANK_SORT_ITEMS * WORKGROUP_SIZE), local);
}
