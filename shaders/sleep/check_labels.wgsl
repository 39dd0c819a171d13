// requires: sleep/common/links.wgsl
// check_labels: one thread per manifold, after the last round of the island search. A link
// between two linkable bodies whose labels still differ means the search did not finish in
// its fixed number of rounds; the flag it raises keeps every island awake this step. When no
// link disagrees, each island's labels all equal its smallest body index, whatever the
// thread order was (that body's label can never go lower).

// Bindings 0 to 4 are links.wgsl's.
// Flagged when some link still joins two labels.
@group(0) @binding(5) var<storage, read_write> unfinished: array<atomic<u32>>;

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
    if labels[m.body_a] != labels[m.body_b] {
        atomicStore(&unfinished[0], 1u);
    }
}
