// requires: common/indexing.wgsl solver/common/body_math.wgsl
// integrate_positions: one thread per body advances its in-step deltas by one substep
// (dynamic bodies' speeds clamped first, the second half of their gyroscopic update after;
// fixed bodies stay).

@group(0) @binding(0) var<uniform> params: SolverParams;
@group(0) @binding(1) var<storage, read> bodies: array<GpuBody>;
// `array<GpuPose>` (start of step, for the gyroscopic half step).
@group(0) @binding(2) var<storage, read> poses: array<GpuPose>;
// `array<GpuVelocity>` (clamped, and turned by the gyroscopic half step, in place).
@group(0) @binding(3) var<storage, read_write> velocities: array<GpuVelocity>;
// `array<GpuSolverBody>`, deltas updated.
@group(0) @binding(4) var<storage, read_write> solver_bodies: array<GpuSolverBody>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= params.body_count {
        return;
    }
    var velocity = velocities[i];
    var state = solver_bodies[i];
    integrate_position(bodies[i], poses[i].rotation, &velocity, &state, params.h);
    velocities[i] = velocity;
    solver_bodies[i] = state;
}
