// requires: common/indexing.wgsl common/layout.wgsl
// check_motion: one thread per body; flags the first body (smallest index) whose pose or
// velocity leaves what a step may leave: a component that is not finite (its exponent bits
// all set: WGSL lets a compiler assume no NaN or infinity, so `x != x` could be folded away)
// or a centre farther than MAX_POSITION from the origin. The host reads the flag after the
// step and, when it is set, checks the flagged state exactly (`tumble_solver::bounds::
// check_motion`) and puts the world back as it was before the step.

override MAX_POSITION: f32;

// The bodies' `WorkList`: `count` bodies (the buffers below may be longer).
@group(0) @binding(0) var<storage, read> body_work: WorkList;
// `array<GpuPose>`, one per body.
@group(0) @binding(1) var<storage, read> poses: array<GpuPose>;
// `array<GpuVelocity>`, one per body.
@group(0) @binding(2) var<storage, read> velocities: array<GpuVelocity>;
// One `u32`: 0 when no body was flagged, else 0xffffffff minus the first flagged index
// (atomicMax keeps the smallest index). Cleared by the host before the step.
@group(0) @binding(3) var<storage, read_write> flag: atomic<u32>;

fn finite4(v: vec4<f32>) -> bool {
    let exponent = bitcast<vec4<u32>>(v) & vec4<u32>(0x7f800000u);
    return all(exponent != vec4<u32>(0x7f800000u));
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= body_work.count {
        return;
    }
    let p = poses[i];
    let v = velocities[i];
    let finite = finite4(p.position) && finite4(p.rotation) && finite4(v.linear)
        && finite4(v.angular);
    // Compared squared in f32: beyond the bound by any margin a float can show, or overflowed
    // to infinity, either way flagged; the host's exact check decides.
    let far = dot(p.position.xyz, p.position.xyz) > MAX_POSITION * MAX_POSITION;
    if !finite || far {
        atomicMax(&flag, 0xffffffffu - i);
    }
}
