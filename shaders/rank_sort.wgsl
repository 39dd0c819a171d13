// requires: common/layout.wgsl
// rank_sort: sorts up to RANK_SORT_ITEMS * WORKGROUP_SIZE (key, value) pairs in place by key,
// then value, equal pairs keeping their order, in one workgroup and one dispatch: for lists
// so short that the radix sort's passes (three dispatches per 4-bit digit) cost far more than
// their work. The pairs are copied to workgroup memory; each item's slot is the number of
// items ordered before it. Both uses give the radix sort's result bit for bit: the bodies'
// values are their input positions, so (key, value) order is the stable order by key; the
// pairs (a, b) are sorted by b and then stably by a, which is (a, b) order.

// The `WorkList` giving the item count (at most RANK_SORT_CAPACITY).
@group(0) @binding(0) var<storage, read> work: WorkList;
// Keys, sorted in place.
@group(0) @binding(1) var<storage, read_write> keys: array<u32>;
// Values, moved with their keys.
@group(0) @binding(2) var<storage, read_write> values: array<u32>;

// Items per thread; the host uses this kernel only for lists of at most
// RANK_SORT_ITEMS * WORKGROUP_SIZE items (tumble-gpu's RANK_SORT_CAPACITY).
override RANK_SORT_ITEMS: u32;

var<workgroup> shared_keys: array<u32, RANK_SORT_ITEMS * WORKGROUP_SIZE>;
var<workgroup> shared_values: array<u32, RANK_SORT_ITEMS * WORKGROUP_SIZE>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(@builtin(local_invocation_index) local: u32) {
    let n = min(work.count, RANK_SORT_ITEMS * WORKGROUP_SIZE);
    for (var i = local; i < n; i += WORKGROUP_SIZE) {
        shared_keys[i] = keys[i];
        shared_values[i] = values[i];
    }
    workgroupBarrier();
    for (var i = local; i < n; i += WORKGROUP_SIZE) {
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
        keys[slot] = key;
        values[slot] = value;
    }
}
