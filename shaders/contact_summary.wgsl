// requires: common/indexing.wgsl common/layout.wgsl
// contact_summary: the step's contact counts in eight words, so that a host asking for them
// reads 32 bytes instead of every manifold: one thread per pair slot folds its manifold into
// its workgroup's totals, and one thread per workgroup adds those to the global ones. Sums of
// integers and the maximum of non-negative floats (ordered as their bits) come out the same
// whatever order the threads run in, so the result is deterministic.

// The pair `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
// Manifolds, one per pair.
@group(0) @binding(1) var<storage, read> manifolds: array<GpuManifold>;
// MAX_MANIFOLD_POINTS points per manifold.
@group(0) @binding(2) var<storage, read> contacts: array<GpuContact>;
// Output, cleared before the dispatch: manifolds with points, their points, the bits of the
// deepest positive overlap (0: none), the pair count, the recycled manifolds; three words
// unused.
@group(0) @binding(3) var<storage, read_write> summary: array<atomic<u32>, 8>;

var<workgroup> group_manifolds: atomic<u32>;
var<workgroup> group_recycled: atomic<u32>;
var<workgroup> group_points: atomic<u32>;
var<workgroup> group_depth: atomic<u32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    if thread.local == 0u {
        atomicStore(&group_manifolds, 0u);
        atomicStore(&group_recycled, 0u);
        atomicStore(&group_points, 0u);
        atomicStore(&group_depth, 0u);
    }
    workgroupBarrier();
    let k = thread_index(thread);
    if k < work.count {
        let len = min(manifolds[k].len, MAX_MANIFOLD_POINTS);
        if len > 0u {
            atomicAdd(&group_manifolds, 1u);
            if manifolds[k].recycled != 0u {
                atomicAdd(&group_recycled, 1u);
            }
            atomicAdd(&group_points, len);
            var deepest = 0.0;
            for (var i = 0u; i < len; i++) {
                deepest = max(deepest, contacts[k * MAX_MANIFOLD_POINTS + i].depth);
            }
            // A positive float's bits order as the float does.
            if deepest > 0.0 {
                atomicMax(&group_depth, bitcast<u32>(deepest));
            }
        }
    }
    workgroupBarrier();
    if thread.local == 0u {
        atomicAdd(&summary[0], atomicLoad(&group_manifolds));
        atomicAdd(&summary[1], atomicLoad(&group_points));
        atomicMax(&summary[2], atomicLoad(&group_depth));
        atomicAdd(&summary[4], atomicLoad(&group_recycled));
        if k == 0u {
            atomicStore(&summary[3], work.count);
        }
    }
}
