// requires: common/layout.wgsl common/sweep.wgsl
// What the two pair-finding kernels, sweep_pairs and long_pairs, share: their bindings, the
// collision-groups test, and how they append a pair.

@group(0) @binding(0) var<uniform> params: SweepParams;
// `array<GpuSweepBox>` in sweep order, from `gather_sweep_boxes`.
@group(0) @binding(1) var<storage, read> sweep_boxes: array<GpuSweepBox>;
// Append counter (`u32`, cleared before the sweep).
@group(0) @binding(2) var<storage, read_write> counter: array<atomic<u32>>;
// Output: smaller body index of each pair.
@group(0) @binding(3) var<storage, read_write> pair_a: array<u32>;
// Output: larger body index of each pair.
@group(0) @binding(4) var<storage, read_write> pair_b: array<u32>;
// The long box count and list from `gather_sweep_boxes`.
@group(0) @binding(5) var<storage, read> long_boxes: array<u32>;
// `array<GpuCollisionGroups>`, one per body: pairs whose groups do not interact are not formed.
@group(0) @binding(6) var<storage, read> groups: array<GpuCollisionGroups>;

// Whether the collision groups of bodies `a` and `b` let them pair (CollisionGroups::
// interacts_with): each one's memberships meet the other's filter.
fn groups_interact(a: u32, b: u32) -> bool {
    let ga = groups[a];
    let gb = groups[b];
    return (ga.memberships & gb.filter_bits) != 0u && (gb.memberships & ga.filter_bits) != 0u;
}

// Appends the pair of `a` and `b` as (smaller index, larger index) through the counter,
// which keeps counting past the capacity.
fn append_pair(a: GpuSweepBox, b: GpuSweepBox) {
    let slot = atomicAdd(&counter[0], 1u);
    if slot < params.pair_capacity {
        pair_a[slot] = min(a.body, b.body);
        pair_b[slot] = max(a.body, b.body);
    }
}
