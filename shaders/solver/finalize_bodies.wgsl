// requires: common/indexing.wgsl solver/common/body_math.wgsl
// finalize_bodies: one thread per body writes the step's deltas into its pose.

@group(0) @binding(0) var<uniform> params: SolverParams;
@group(0) @binding(1) var<storage, read> bodies: array<GpuBody>;
@group(0) @binding(2) var<storage, read> solver_bodies: array<GpuSolverBody>;
// `array<GpuPose>`, updated.
@group(0) @binding(3) var<storage, read_write> poses: array<GpuPose>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= params.body_count {
        return;
    }
    poses[i] = finalize_pose(bodies[i].kind, poses[i], solver_bodies[i]);
}
