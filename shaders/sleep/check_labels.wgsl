// requires: common/indexing.wgsl sleep/common/sleep_constants.wgsl
// check_labels: one thread per manifold, after the last round of the island search. A link
// between two linkable bodies whose labels still differ means the search did not finish in
// its fixed number of rounds; the flag it raises keeps every island awake this step. When no
// link disagrees, each island's labels all equal its smallest body index, whatever the
// thread order was (that body's label can never go lower).

@group(0) @binding(0) var<storage, read> work: WorkList;
@group(0) @binding(1) var<storage, read> manifolds: array<GpuManifold>;
@group(0) @binding(2) var<storage, read> awake_bodies: array<GpuBody>;
@group(0) @binding(3) var<storage, read> island: array<u32>;
@group(0) @binding(4) var<storage, read> labels: array<u32>;
@group(0) @binding(5) var<storage, read_write> unfinished: array<atomic<u32>>;

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
    if labels[a] != labels[b] {
        atomicStore(&unfinished[0], 1u);
    }
}
