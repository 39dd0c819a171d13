// requires: common/indexing.wgsl common/layout.wgsl common/sweep.wgsl
// gather_sweep_boxes: one thread per sorted position copies that body's AABB into sweep
// order, sweep axis first, with its index and flags, so that sweep_pairs reads contiguous
// records instead of gathering from the per-body arrays at every step of its scan. A box
// longer on the sweep axis than `params.long_extent` is counted in `long_boxes[0]` and
// listed after it while there is room (see common/sweep.wgsl); the host clears the count.

// The bodies' `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
// `SweepAxis` from `choose_axis`.
@group(0) @binding(1) var<storage, read> sweep_axis: SweepAxis;
@group(0) @binding(2) var<storage, read> aabbs: array<GpuAabb>;
// `array<GpuShape>` (for the flags).
@group(0) @binding(3) var<storage, read> shapes: array<GpuShape>;
// Body indices sorted by lower bound on the sweep axis.
@group(0) @binding(4) var<storage, read> sorted_bodies: array<u32>;
// Output `array<GpuSweepBox>`, one per sorted position.
@group(0) @binding(5) var<storage, read_write> sweep_boxes: array<GpuSweepBox>;
// SweepParams (the long extent).
@group(0) @binding(6) var<uniform> params: SweepParams;
// Output: the long box count and list (cleared count before).
@group(0) @binding(7) var<storage, read_write> long_boxes: array<atomic<u32>>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let p = thread_index(thread);
    if p >= work.count {
        return;
    }
    let i = sorted_bodies[p];
    let b = aabbs[i];
    let a0 = sweep_axis.axis;
    let a1 = (a0 + 1u) % 3u;
    let a2 = (a0 + 2u) % 3u;
    let sweep_box = GpuSweepBox(
        b.min[a0], b.min[a1], b.min[a2], i,
        b.max[a0], b.max[a1], b.max[a2], shapes[i].flags,
    );
    sweep_boxes[p] = sweep_box;
    if is_long(sweep_box, params.long_extent, true) {
        let k = atomicAdd(&long_boxes[0], 1u);
        if k < MAX_LONG_BOXES {
            atomicStore(&long_boxes[1u + k], p);
        }
    }
}
