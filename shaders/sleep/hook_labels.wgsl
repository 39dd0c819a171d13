// requires: common/indexing.wgsl sleep/common/sleep_constants.wgsl
// hook_labels: one thread per manifold, one round of the island search. A manifold with
// points between two linkable bodies whose labels differ points the larger label at the
// smaller one. Labels are read from `labels` and lowered in `next_labels` (a copy of them
// made by the previous round), so every thread sees the same labels and atomicMin, being
// commutative, gives the same result in any thread order.

@group(0) @binding(0) var<storage, read> work: WorkList;
@group(0) @binding(1) var<storage, read> manifolds: array<GpuManifold>;
@group(0) @binding(2) var<storage, read> awake_bodies: array<GpuBody>;
@group(0) @binding(3) var<storage, read> island: array<u32>;
@group(0) @binding(4) var<storage, read> labels: array<u32>;
@group(0) @binding(5) var<storage, read_write> next_labels: array<atomic<u32>>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let k = thread_index(thread);
    if k >= work.count {
        return;
    }
    let m = manifolds[k];
    if m.len == 0u {
        return;
    }
    let a = m.body_a;
    let b = m.body_b;
    if !is_linkable(awake_bodies[a].kind, island[a]) || !is_linkable(awake_bodies[b].kind, island[b]) {
        return;
    }
    let label_a = labels[a];
    let label_b = labels[b];
    if label_a != label_b {
        atomicMin(&next_labels[max(label_a, label_b)], min(label_a, label_b));
    }
}
