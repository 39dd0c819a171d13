// requires: common/indexing.wgsl solver/common/store_slot.wgsl
// store_impulses: one thread per constraint slot writes the final impulses of the manifold
// there (store_slot.wgsl). Runs before finalize_bodies: the poses are still those the
// manifolds were made from.

// The contacts' `WorkList`.
@group(0) @binding(0) var<storage, read> contact_work: WorkList;
// Manifold indices by color: the manifold of each constraint slot.
@group(0) @binding(1) var<storage, read> color_order: array<u32>;
// The constraint store (`GpuConstraint` rows, by slot).
@group(0) @binding(2) var<storage, read> constraints: array<vec4<f32>>;
// `array<GpuPose>` (still the start of the step).
@group(0) @binding(3) var<storage, read> poses: array<GpuPose>;
// `array<GpuContact>` (points), impulses updated.
@group(0) @binding(4) var<storage, read_write> contacts: array<GpuContact>;
// Output `array<GpuTilt>` for the next step.
@group(0) @binding(5) var<storage, read_write> tilts: array<GpuTilt>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let s = thread_index(thread);
    if s >= contact_work.count {
        return;
    }
    store_slot(s);
}
