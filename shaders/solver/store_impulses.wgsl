// requires: common/indexing.wgsl solver/common/contact_math.wgsl solver/common/constraint_store.wgsl
// store_impulses: one thread per constraint slot writes the final impulses of the manifold
// there (color_order[slot]) into its
// contact points, where the next step's carry_impulses finds them for warm starting, and its
// tilt impulse (with the normal in body A's frame) where the next step's prepare_contacts
// finds it through the manifold's `previous` index. Runs before finalize_bodies: the poses
// are still those the manifolds were made from.

@group(0) @binding(0) var<storage, read> contact_work: WorkList;
@group(0) @binding(1) var<storage, read> color_order: array<u32>;
@group(0) @binding(2) var<storage, read> constraints: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> poses: array<GpuPose>;
@group(0) @binding(4) var<storage, read_write> contacts: array<GpuContact>;
@group(0) @binding(5) var<storage, read_write> tilts: array<GpuTilt>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let s = thread_index(thread);
    if s >= contact_work.count {
        return;
    }
    let i = color_order[s];
    let c = load_constraint(s);
    for (var p = 0u; p < c.point_count; p++) {
        let slot = i * MAX_MANIFOLD_POINTS + p;
        contacts[slot] = stored_point(c, p, contacts[slot]);
    }
    tilts[i] = stored_tilt(c, poses[c.body_a].rotation);
}
