// requires: common/indexing.wgsl common/layout.wgsl common/contact_events.wgsl
// contact_ends: one thread per pair of last step, after contact_begins. A pair that touched
// then and whose slot contact_begins did not mark kept (it does not touch now, or is no pair
// any more) gets an end event, with last step's impulse and point.

// Last step's pair `WorkList`.
@group(0) @binding(0) var<storage, read> previous_work: WorkList;
// Last step's manifolds.
@group(0) @binding(1) var<storage, read> previous_manifolds: array<GpuManifold>;
// Last step's points.
@group(0) @binding(2) var<storage, read> previous_contacts: array<GpuContact>;
// `contact_begins`' marks.
@group(0) @binding(3) var<storage, read> kept: array<u32>;
// The append counters.
@group(0) @binding(4) var<storage, read_write> counts: EventCounts;
// Output: the ends, after the begins.
@group(0) @binding(5) var<storage, read_write> events: array<GpuContactEvent>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let j = thread_index(thread);
    if j >= previous_work.count || kept[j] != 0u {
        return;
    }
    let old = previous_manifolds[j];
    var before = touch_start();
    for (var i = 0u; i < min(old.len, MAX_MANIFOLD_POINTS); i++) {
        before = touch_add(before, previous_contacts[j * MAX_MANIFOLD_POINTS + i]);
    }
    if !before.touches {
        return;
    }
    let e = atomicAdd(&counts.events, 1u);
    if e < arrayLength(&events) {
        events[e] = touch_event(EVENT_END, old, j, before);
    }
}
