// requires: common/indexing.wgsl common/layout.wgsl
// write_sort_keys: one thread per body; the AABB's lower bound on the sweep axis becomes an
// unsigned key whose integer order is the float order, paired with the body index.

// The bodies' `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
// `SweepAxis` from `choose_axis`.
@group(0) @binding(1) var<storage, read> sweep_axis: SweepAxis;
@group(0) @binding(2) var<storage, read> aabbs: array<GpuAabb>;
// Output keys, one per body.
@group(0) @binding(3) var<storage, read_write> keys: array<u32>;
// Output body indices, one per body.
@group(0) @binding(4) var<storage, read_write> values: array<u32>;

// Flips all bits of negative floats and only the sign bit of positive ones, so that
// unsigned comparison of keys orders like float comparison. -0.0 first becomes +0.0: the
// two compare equal as floats and must get one key.
fn order_key(x: f32) -> u32 {
    var bits = bitcast<u32>(x);
    if bits == 0x80000000u {
        bits = 0u;
    }
    if (bits & 0x80000000u) != 0u {
        return ~bits;
    }
    return bits | 0x80000000u;
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= work.count {
        return;
    }
    keys[i] = order_key(aabbs[i].min[sweep_axis.axis]);
    values[i] = i;
}
