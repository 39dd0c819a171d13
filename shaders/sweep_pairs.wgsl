// sweep_pairs: one thread per body in sorted order scans forward while the next box's lower
// bound on the sweep axis is not past its upper bound, tests the other two axes (closed
// intervals: touching boxes pair, as on the CPU), and appends each overlapping pair as
// (smaller index, larger index) through an atomic counter. Static-static pairs are skipped.
// The counter keeps counting past the capacity, so an overflow is reported, never hidden.

@group(0) @binding(0) var<uniform> params: SweepParams;
@group(0) @binding(1) var<storage, read> sweep_axis: SweepAxis;
@group(0) @binding(2) var<storage, read> aabbs: array<GpuAabb>;
@group(0) @binding(3) var<storage, read> shapes: array<GpuShape>;
@group(0) @binding(4) var<storage, read> sorted_bodies: array<u32>;
@group(0) @binding(5) var<storage, read_write> counter: array<atomic<u32>>;
@group(0) @binding(6) var<storage, read_write> pair_a: array<u32>;
@group(0) @binding(7) var<storage, read_write> pair_b: array<u32>;

fn overlaps(a: GpuAabb, b: GpuAabb) -> bool {
    return all(a.min.xyz <= b.max.xyz) && all(b.min.xyz <= a.max.xyz);
}

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
    let axis = sweep_axis.axis;
    let i = sorted_bodies[p];
    let box_i = aabbs[i];
    let static_i = (shapes[i].flags & BODY_STATIC) != 0u;
    let reach = box_i.max[axis];
    for (var q = p + 1u; q < params.body_count; q++) {
        let j = sorted_bodies[q];
        let box_j = aabbs[j];
        // Boxes are sorted by lower bound: once one starts past our upper bound, all do.
        if box_j.min[axis] > reach {
            break;
        }
        let static_j = (shapes[j].flags & BODY_STATIC) != 0u;
        if (static_i && static_j) || !overlaps(box_i, box_j) {
            continue;
        }
        let slot = atomicAdd(&counter[0], 1u);
        if slot < params.pair_capacity {
            pair_a[slot] = min(i, j);
            pair_b[slot] = max(i, j);
        }
    }
}
