// requires: common/layout.wgsl
// plan_dispatch: one thread turns an append counter into a WorkList: the count clamped to
// the buffer's capacity (set by the host), the raw count (so overflow is visible), and the
// workgroup counts of the indirect dispatches that process the list. This keeps a
// data-dependent count on the GPU: no step ever waits for the host to read it.

// The append counter (`u32` at offset 0).
@group(0) @binding(0) var<storage, read> counter: array<u32>;
// The `WorkList` to fill; its `capacity` is set by the host when the list is allocated.
@group(0) @binding(1) var<storage, read_write> work: WorkList;

@compute @workgroup_size(1)
fn main() {
    let requested = counter[0];
    let count = min(requested, work.capacity);
    let groups = (count + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    // Fold past the per-dimension limit exactly as the host's workgroups_for does.
    var x = groups;
    var y = 1u;
    if groups > MAX_WORKGROUPS_PER_DIMENSION {
        x = MAX_WORKGROUPS_PER_DIMENSION;
        y = (groups + MAX_WORKGROUPS_PER_DIMENSION - 1u) / MAX_WORKGROUPS_PER_DIMENSION;
    }
    work.count = count;
    work.requested = requested;
    work.groups = DispatchArgs(x, y, 1u, 0u);
}
