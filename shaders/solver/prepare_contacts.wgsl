// requires: common/indexing.wgsl solver/common/prepare_constraint.wgsl
// prepare_contacts: one thread per slot of the order by color builds the constraint of the
// manifold there (a manifold without points gives an empty constraint): normal and two
// friction rows per point, effective masses, anchors, softness, and the warm-start impulses
// the collision stage carried over.

@group(0) @binding(0) var<uniform> params: SolverParams;
// The contacts' `WorkList`.
@group(0) @binding(1) var<storage, read> contact_work: WorkList;
@group(0) @binding(2) var<storage, read> manifolds: array<GpuManifold>;
// `array<GpuContact>`, `MAX_MANIFOLD_POINTS` per manifold, with carried impulses.
@group(0) @binding(3) var<storage, read> contacts: array<GpuContact>;
@group(0) @binding(4) var<storage, read> bodies: array<GpuBody>;
@group(0) @binding(5) var<storage, read> poses: array<GpuPose>;
@group(0) @binding(6) var<storage, read> velocities: array<GpuVelocity>;
// `array<GpuSolverBody>` from `prepare_bodies`.
@group(0) @binding(7) var<storage, read> solver_bodies: array<GpuSolverBody>;
// Last step's `array<GpuTilt>`, indexed by the manifolds' `previous`.
@group(0) @binding(8) var<storage, read> previous_tilts: array<GpuTilt>;
// Manifold indices by color: slot `s` holds the constraint of manifold `color_order[s]`.
@group(0) @binding(9) var<storage, read> color_order: array<u32>;
// Output: the constraint store (`GpuConstraint` rows, by slot).
@group(0) @binding(10) var<storage, read_write> constraints: array<vec4<f32>>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let s = thread_index(thread);
    if s >= contact_work.count {
        return;
    }
    prepare_constraint(color_order[s], s);
}
