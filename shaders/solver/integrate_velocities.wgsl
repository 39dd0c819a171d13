// requires: common/indexing.wgsl solver/common/body_math.wgsl
// integrate_velocities: one thread per body advances a dynamic body's velocity by one
// substep (gravity, gyroscopic term, damping, locks).

@group(0) @binding(0) var<uniform> params: SolverParams;
@group(0) @binding(1) var<storage, read> bodies: array<GpuBody>;
// `array<GpuPose>` (start of step).
@group(0) @binding(2) var<storage, read> poses: array<GpuPose>;
// `array<GpuSolverBody>` (for the delta rotation).
@group(0) @binding(3) var<storage, read> solver_bodies: array<GpuSolverBody>;
// `array<GpuVelocity>`, updated.
@group(0) @binding(4) var<storage, read_write> velocities: array<GpuVelocity>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= params.body_count {
        return;
    }
    velocities[i] = integrate_velocity(
        bodies[i],
        poses[i].rotation,
        solver_bodies[i],
        velocities[i],
        params.gravity.xyz,
        params.h,
    );
}
