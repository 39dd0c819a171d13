// requires: common/indexing.wgsl common/layout.wgsl common/contact_events.wgsl
// contact_begins: one thread per pair of this step, after the solver. A pair that touches is
// appended to the touching list; if its manifold of last step (found by match_pairs) did not
// touch, or it had none, a begin event is appended; if it did, last step's slot is marked
// kept, so that contact_ends leaves it alone. Append order is the threads' (the host sorts
// the short lists by body pair).

// This step's pair `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
// This step's manifolds, one per pair.
@group(0) @binding(1) var<storage, read> manifolds: array<GpuManifold>;
// This step's points, `MAX_MANIFOLD_POINTS` per pair.
@group(0) @binding(2) var<storage, read> contacts: array<GpuContact>;
// Last step's manifolds.
@group(0) @binding(3) var<storage, read> previous_manifolds: array<GpuManifold>;
// Last step's points.
@group(0) @binding(4) var<storage, read> previous_contacts: array<GpuContact>;
// Output: 1 for each of last step's slots that still touches (cleared before).
@group(0) @binding(5) var<storage, read_write> kept: array<u32>;
// The append counters `EventCounts` (cleared before).
@group(0) @binding(6) var<storage, read_write> counts: EventCounts;
// Output `array<GpuContactEvent>`: begins (then ends, from `contact_ends`).
@group(0) @binding(7) var<storage, read_write> events: array<GpuContactEvent>;
// Output `array<GpuContactEvent>`: the pairs touching.
@group(0) @binding(8) var<storage, read_write> touching: array<GpuContactEvent>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let k = thread_index(thread);
    if k >= work.count {
        return;
    }
    let m = manifolds[k];
    var now = touch_start();
    for (var i = 0u; i < min(m.len, MAX_MANIFOLD_POINTS); i++) {
        now = touch_add(now, contacts[k * MAX_MANIFOLD_POINTS + i]);
    }
    if !now.touches {
        return;
    }
    let t = atomicAdd(&counts.touching, 1u);
    if t < arrayLength(&touching) {
        touching[t] = touch_event(EVENT_TOUCHING, m, k, now);
    }
    var before = touch_start();
    let j = m.previous;
    if j != NO_PREVIOUS && j < arrayLength(&previous_manifolds) {
        let old = previous_manifolds[j];
        for (var i = 0u; i < min(old.len, MAX_MANIFOLD_POINTS); i++) {
            before = touch_add(before, previous_contacts[j * MAX_MANIFOLD_POINTS + i]);
        }
    }
    if before.touches {
        kept[j] = 1u;
        return;
    }
    let e = atomicAdd(&counts.events, 1u);
    if e < arrayLength(&events) {
        events[e] = touch_event(EVENT_BEGIN, m, k, now);
    }
}
