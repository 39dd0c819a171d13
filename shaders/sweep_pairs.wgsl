// sweep_pairs: one thread per body in sorted order scans forward while the next box's lower
// bound on the sweep axis is not past its upper bound, tests the other two axes (closed
// intervals: touching boxes pair, as on the CPU), and appends each overlapping pair as
// (smaller index, larger index) through an atomic counter. Static-static pairs are skipped.
// The counter keeps counting past the capacity, so an overflow is reported, never hidden.
// On the sweep axis the test is implied: sorted lower bounds make lo_p <= lo_q <= hi_q.

@group(0) @binding(0) var<uniform> params: SweepParams;
@group(0) @binding(1) var<storage, read> sweep_boxes: array<GpuSweepBox>;
@group(0) @binding(2) var<storage, read_write> counter: array<atomic<u32>>;
@group(0) @binding(3) var<storage, read_write> pair_a: array<u32>;
@group(0) @binding(4) var<storage, read_write> pair_b: array<u32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let p = linear_index(workgroup, groups, local);
    if p >= params.body_count {
        return;
    }
    let me = sweep_boxes[p];
    let is_static = (me.flags & BODY_STATIC) != 0u;
    for (var q = p + 1u; q < params.body_count; q++) {
        let other = sweep_boxes[q];
        // Boxes are sorted by lower bound: once one starts past our upper bound, all do.
        if other.lo_0 > me.hi_0 {
            break;
        }
        let overlaps = other.lo_1 <= me.hi_1 && me.lo_1 <= other.hi_1
            && other.lo_2 <= me.hi_2 && me.lo_2 <= other.hi_2;
        if !overlaps || (is_static && (other.flags & BODY_STATIC) != 0u) {
            continue;
        }
        let slot = atomicAdd(&counter[0], 1u);
        if slot < params.pair_capacity {
            pair_a[slot] = min(me.body, other.body);
            pair_b[slot] = max(me.body, other.body);
        }
    }
}
