// requires: common/indexing.wgsl common/layout.wgsl common/sweep.wgsl
// write_sort_keys: one thread per body; the AABB's lower bound on the sweep axis becomes an
// unsigned key whose integer order is the float order (led by the body's world when the step
// holds several: common/sweep.wgsl's sweep_key), paired with the body index.

// The bodies' `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
// `SweepAxis` from `choose_axis`.
@group(0) @binding(1) var<storage, read> sweep_axis: SweepAxis;
@group(0) @binding(2) var<storage, read> aabbs: array<GpuAabb>;
// Output keys, one per body.
@group(0) @binding(3) var<storage, read_write> keys: array<u32>;
// Output body indices, one per body.
@group(0) @binding(4) var<storage, read_write> values: array<u32>;
// `array<GpuShape>` (for the world in the flags).
@group(0) @binding(5) var<storage, read> shapes: array<GpuShape>;
// SweepParams (the world bits).
@group(0) @binding(6) var<uniform> params: SweepParams;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= work.count {
        return;
    }
    let world = shapes[i].flags >> BODY_WORLD_SHIFT;
    keys[i] = sweep_key(world, aabbs[i].min[sweep_axis.axis], params.world_bits);
    values[i] = i;
}
