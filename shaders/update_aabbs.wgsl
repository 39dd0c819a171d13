// requires: common/indexing.wgsl common/quat.wgsl
// update_aabbs: one thread per body; pose, velocity and cuboid -> world AABB grown by the
// speculative margin and swept by the motion expected over the next step.

@group(0) @binding(0) var<uniform> params: UpdateAabbsParams;
// `array<GpuPose>`, one per body.
@group(0) @binding(1) var<storage, read> poses: array<GpuPose>;
// `array<GpuVelocity>`, one per body.
@group(0) @binding(2) var<storage, read> velocities: array<GpuVelocity>;
// `array<GpuShape>`, one per body.
@group(0) @binding(3) var<storage, read> shapes: array<GpuShape>;
// Output `array<GpuAabb>`, one per body.
@group(0) @binding(4) var<storage, read_write> aabbs: array<GpuAabb>;

fn swept_aabb(pose: GpuPose, velocity: GpuVelocity, shape: GpuShape) -> GpuAabb {
    let r = quat_to_mat3(pose.rotation);
    let h = vec3<f32>(shape.hx, shape.hy, shape.hz);
    // World half extent along axis i is sum_j |R_ij| h_j: exact for a rotated box.
    let extent = abs(r[0]) * h.x + abs(r[1]) * h.y + abs(r[2]) * h.z;
    // A point at distance |h| from the centre moves at most |w| |h| dt along its arc while
    // rotating: a conservative bound on how far any corner can travel.
    let spin = length(velocity.angular.xyz) * length(h) * params.dt;
    let grow = extent + vec3<f32>(params.margin + spin);
    let centre = pose.position.xyz;
    let travel = velocity.linear.xyz * params.dt;
    let lo = centre - grow + min(travel, vec3<f32>(0.0));
    let hi = centre + grow + max(travel, vec3<f32>(0.0));
    return GpuAabb(vec4<f32>(lo, 0.0), vec4<f32>(hi, 0.0));
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= params.count {
        return;
    }
    aabbs[i] = swept_aabb(poses[i], velocities[i], shapes[i]);
}
