// requires: sleep/common/links.wgsl
// hook_labels: one thread per manifold, one round of the island search. A manifold with
// points between two linkable bodies whose labels differ points the larger label at the
// smaller one. Labels are read from `labels` and lowered in `next_labels` (a copy of them
// made by the previous round), so every thread sees the same labels and atomicMin, being
// commutative, gives the same result in any thread order.

// Bindings 0 to 4 are links.wgsl's.
// The labels the round's hooks lower.
@group(0) @binding(5) var<storage, read_write> next_labels: array<atomic<u32>>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let k = thread_index(thread);
    if k >= work.count {
        return;
    }
    let m = manifolds[k];
    if !is_link(m) {
        return;
    }
    let label_a = labels[m.body_a];
    let label_b = labels[m.body_b];
    if label_a != label_b {
        atomicMin(&next_labels[max(label_a, label_b)], min(label_a, label_b));
    }
}
