// requires: common/indexing.wgsl common/layout.wgsl
// remap_pairs: one thread per pair of last step's sorted list renumbers its bodies after the
// bodies were uploaded again in a new order (a batch of worlds whose worlds or bodies came or
// went): `remap[old]` is the body's new index, or REMAP_DROPPED with the index at which its
// world's pairs are dropped, as forget_pairs drops them. A kept world's bodies keep their
// order and move by one offset, and the worlds keep theirs, so the list stays sorted for
// match_pairs' binary search (crates/tumble-gpu/src/kernels/remap_pairs.rs has the argument).

// Last step's pair `WorkList`.
@group(0) @binding(0) var<storage, read> previous_work: WorkList;
// Last step's sorted pairs, first bodies.
@group(0) @binding(1) var<storage, read_write> previous_a: array<u32>;
// Last step's sorted pairs, second bodies.
@group(0) @binding(2) var<storage, read_write> previous_b: array<u32>;
// Per old body: its new index, or REMAP_DROPPED | the index its world's pairs drop to.
@group(0) @binding(3) var<storage, read> remap: array<u32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= previous_work.count {
        return;
    }
    let a = remap[previous_a[i]];
    if (a & REMAP_DROPPED) != 0u {
        let f = a & ~REMAP_DROPPED;
        previous_a[i] = f;
        previous_b[i] = f;
        return;
    }
    previous_a[i] = a;
    previous_b[i] = remap[previous_b[i]];
}
