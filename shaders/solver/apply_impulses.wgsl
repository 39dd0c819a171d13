// requires: common/indexing.wgsl solver/common/body_math.wgsl
// apply_impulses: one thread applies the impulses the host queued since the last step, in
// the order they were queued (several may hit one body), to dynamic bodies: v += M^-1 j,
// w += I^-1 (r x j) with the world inverse inertia of the body's current pose.

// `array<GpuImpulse>`, exactly the queued ones.
@group(0) @binding(0) var<storage, read> impulses: array<GpuImpulse>;
@group(0) @binding(1) var<storage, read> bodies: array<GpuBody>;
@group(0) @binding(2) var<storage, read> poses: array<GpuPose>;
// `array<GpuVelocity>`, updated.
@group(0) @binding(3) var<storage, read_write> velocities: array<GpuVelocity>;

@compute @workgroup_size(1)
fn main() {
    for (var k = 0u; k < arrayLength(&impulses); k++) {
        let queued = impulses[k];
        let body = bodies[queued.body];
        if body.kind != BODY_DYNAMIC {
            continue;
        }
        let pose = poses[queued.body];
        let j = queued.impulse.xyz;
        let r = queued.point.xyz - pose.position.xyz;
        let dv = translation_mask(body.locks) * body.inverse_inertia.w * j;
        let dw = world_inverse_inertia(body, pose.rotation) * cross(r, j);
        var velocity = velocities[queued.body];
        velocity.linear = vec4<f32>(velocity.linear.xyz + dv, 0.0);
        velocity.angular = vec4<f32>(velocity.angular.xyz + dw, 0.0);
        velocities[queued.body] = velocity;
    }
}
