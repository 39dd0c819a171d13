// requires: common/layout.wgsl common/rank_sort_in_place.wgsl
// sort_world_bodies: the broad phase's body sort for a step of several worlds, each of at
// most RANK_SORT_ITEMS * WORKGROUP_SIZE bodies: one workgroup per world rank-sorts that
// world's (key, body) pairs in place (common/rank_sort.wgsl). A world's bodies are one run of
// indices and its keys lead with its index (common/sweep.wgsl's sweep_key), so the whole list
// in key order is every world's run in key order, one world after the other: the radix
// sort's stable order bit for bit, in one dispatch instead of 24 over every body of the batch.

// [0]: the world count; then world w's bodies are
// `world_body_starts[1 + w]..world_body_starts[2 + w]`.
@group(0) @binding(0) var<storage, read> world_body_starts: array<u32>;
// Keys, sorted in place.
@group(0) @binding(1) var<storage, read_write> keys: array<u32>;
// Values (body indices), moved with their keys.
@group(0) @binding(2) var<storage, read_write> values: array<u32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let first = world_body_starts[1u + group.x];
    let count = min(world_body_starts[2u + group.x] - first, RANK_SORT_ITEMS * WORKGROUP_SIZE);
    rank_sort_range(first, count, local);
}
