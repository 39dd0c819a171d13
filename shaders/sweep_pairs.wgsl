// requires: common/indexing.wgsl common/pair_output.wgsl
// sweep_pairs: each body, in sorted order, scans forward while the next box's lower bound
// on the sweep axis is not past its upper bound, tests the other two axes (closed
// intervals: touching boxes pair, as on the CPU), and appends each overlapping pair as
// (smaller index, larger index) through an atomic counter. Static-static pairs and pairs whose
// collision groups do not interact are skipped, and so are long boxes, which long_pairs pairs (common/sweep.wgsl).
// The counter keeps counting past the capacity, so an overflow is reported, never hidden.
// Bodies are sorted by world, then by lower bound (common/sweep.wgsl's sweep_key; with
// several worlds the keys keep only the bound's top bits, so bounds in one key's range may
// be out of order and both sides of the sweep axis are tested).
//
// A workgroup takes 256 consecutive bodies, whose scan windows nearly coincide, and walks
// the candidates in tiles of 256 boxes loaded once into workgroup memory and shared by all
// its threads, until no thread's window reaches the next tile: one global read per box per
// workgroup instead of one per box per thread.

// The bindings are common/pair_output.wgsl's.

var<workgroup> candidates: array<GpuSweepBox, WORKGROUP_SIZE>;
var<workgroup> still_scanning: atomic<u32>;
var<workgroup> continue_flag: u32;

// Tests one candidate against `me` and appends the pair when it overlaps.
fn test_pair(me: GpuSweepBox, other: GpuSweepBox) {
    // The world follows from the keys' lead bits; the sweep axis only from exact keys (one
    // world): with several, bounds closer than a key's dropped bits share a key, so both
    // sides are tested.
    if other.lo_0 > me.hi_0 || other.hi_0 < me.lo_0 || !overlap_12(me, other)
        || both_static(me, other) || !groups_interact(me.body, other.body) {
        return;
    }
    append_pair(me, other);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let n = params.body_count;
    let listed = long_boxes_listed(long_boxes[0]);
    let first = thread_group(thread) * WORKGROUP_SIZE;
    let p = first + thread.local;
    let world_bits = params.world_bits;
    var scanning = p < n;
    var me: GpuSweepBox;
    var hi_key = 0u;
    if scanning {
        me = sweep_boxes[p];
        scanning = !is_long(me, params.long_extent, listed);
        hi_key = sweep_key(box_world(me), me.hi_0, world_bits);
    }
    // Candidates start right after the workgroup's first body.
    var start = first + 1u;
    loop {
        if thread.local == 0u {
            atomicStore(&still_scanning, 0u);
        }
        if start + thread.local < n {
            candidates[thread.local] = sweep_boxes[start + thread.local];
        }
        workgroupBarrier();
        if scanning {
            let end = min(WORKGROUP_SIZE, n - min(start, n));
            for (var j = 0u; j < end; j++) {
                if start + j <= p {
                    continue;
                }
                let other = candidates[j];
                // Sorted by key: once one's key is past our upper bound's, all are (a box of
                // a later world has a larger key than any of ours).
                if sweep_key(box_world(other), other.lo_0, world_bits) > hi_key {
                    scanning = false;
                    break;
                }
                if !is_long(other, params.long_extent, listed) {
                    test_pair(me, other);
                }
            }
            if start + WORKGROUP_SIZE >= n {
                scanning = false;
            }
        }
        if scanning {
            atomicOr(&still_scanning, 1u);
        }
        workgroupBarrier();
        if thread.local == 0u {
            continue_flag = atomicLoad(&still_scanning);
        }
        // The barrier inside the uniform load also keeps the next tile's loads after every
        // thread is done reading this one.
        if workgroupUniformLoad(&continue_flag) == 0u {
            break;
        }
        start += WORKGROUP_SIZE;
    }
}
