// requires: common/indexing.wgsl solver/common/body_math.wgsl
// prepare_bodies: one thread per body resets its in-step deltas and puts its inverse mass and
// inverse inertia in world axes for the step.

@group(0) @binding(0) var<uniform> params: SolverParams;
@group(0) @binding(1) var<storage, read> bodies: array<GpuBody>;
@group(0) @binding(2) var<storage, read> poses: array<GpuPose>;
// Output `array<GpuSolverBody>`.
@group(0) @binding(3) var<storage, read_write> solver_bodies: array<GpuSolverBody>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= params.body_count {
        return;
    }
    solver_bodies[i] = prepare_body(bodies[i], poses[i]);
}
