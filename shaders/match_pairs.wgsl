// requires: common/indexing.wgsl common/layout.wgsl
// match_pairs: one thread per pair finds the same pair in last step's sorted pair list by
// binary search (the lists are in canonical (a, b) order), so its manifold and impulses can be
// carried over. NO_PREVIOUS when the pair is new.

// This step's pair `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
// This step's sorted pairs, first bodies.
@group(0) @binding(1) var<storage, read> pair_a: array<u32>;
// This step's sorted pairs, second bodies.
@group(0) @binding(2) var<storage, read> pair_b: array<u32>;
// Last step's pair `WorkList`.
@group(0) @binding(3) var<storage, read> previous_work: WorkList;
// Last step's sorted pairs, first bodies.
@group(0) @binding(4) var<storage, read> previous_a: array<u32>;
// Last step's sorted pairs, second bodies.
@group(0) @binding(5) var<storage, read> previous_b: array<u32>;
// Output: last step's index of each pair, or `NO_PREVIOUS`.
@group(0) @binding(6) var<storage, read_write> previous_index: array<u32>;

// True when (a1, b1) sorts before (a2, b2).
fn pair_less(a1: u32, b1: u32, a2: u32, b2: u32) -> bool {
    return a1 < a2 || (a1 == a2 && b1 < b2);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let k = thread_index(thread);
    if k >= work.count {
        return;
    }
    let a = pair_a[k];
    let b = pair_b[k];
    // Lower bound: the first previous pair not before (a, b).
    var lo = 0u;
    var hi = previous_work.count;
    while lo < hi {
        let mid = lo + (hi - lo) / 2u;
        if pair_less(previous_a[mid], previous_b[mid], a, b) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    var found = NO_PREVIOUS;
    if lo < previous_work.count && previous_a[lo] == a && previous_b[lo] == b {
        found = lo;
    }
    previous_index[k] = found;
}
