// requires: common/indexing.wgsl common/layout.wgsl
// forget_pairs: one thread per pair of last step's sorted list drops the pairs of the worlds
// being reset from it, so that match_pairs finds none of them and their manifolds, impulses
// and color seeds are not carried: the next step meets those worlds as a world met for the
// first time. A dropped pair becomes (f, f), with f its world's first body: no step has a
// pair of one body, and since a world's bodies are one run and the list is sorted by pair,
// every pair before the world's sorts before (f, f) and every pair after it not before, so
// the list stays sorted for match_pairs' binary search.

// Last step's pair `WorkList`.
@group(0) @binding(0) var<storage, read> previous_work: WorkList;
// Last step's sorted pairs, first bodies.
@group(0) @binding(1) var<storage, read_write> previous_a: array<u32>;
// Last step's sorted pairs, second bodies.
@group(0) @binding(2) var<storage, read_write> previous_b: array<u32>;
// `array<GpuShape>` (the world in the flags).
@group(0) @binding(3) var<storage, read> shapes: array<GpuShape>;
// Per world: 0 to keep its pairs, else its first body plus one.
@group(0) @binding(4) var<storage, read> forget: array<u32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= previous_work.count {
        return;
    }
    let world = shapes[previous_a[i]].flags >> BODY_WORLD_SHIFT;
    let first = forget[world];
    if first != 0u {
        previous_a[i] = first - 1u;
        previous_b[i] = first - 1u;
    }
}
