// requires: common/indexing.wgsl sleep/common/sleep_constants.wgsl
// touch_sleepers: one thread per manifold of the step. A manifold with points (speculative
// ones included, the same condition that links islands) between an awake body and a
// sleeping one flags the sleeping body's island to wake at the start of the next step; this
// step it was an immovable obstacle. A manifold with a moving kinematic body keeps both its
// bodies from resting (a body carried or pushed by one must not fall asleep on it).

// The step's pair `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
// `array<GpuManifold>`: the step's manifolds.
@group(0) @binding(1) var<storage, read> manifolds: array<GpuManifold>;
// `array<GpuBody>`: every body as uploaded.
@group(0) @binding(2) var<storage, read> awake_bodies: array<GpuBody>;
// `array<GpuVelocity>`: the step's final velocities.
@group(0) @binding(3) var<storage, read> velocities: array<GpuVelocity>;
// `array<u32>`: island labels.
@group(0) @binding(4) var<storage, read> island: array<u32>;
// `array<f32>`: rest times, reset next to moving kinematic bodies.
@group(0) @binding(5) var<storage, read_write> rest_time: array<f32>;
// `array<atomic<u32>>`: wake flags by island label, set.
@group(0) @binding(6) var<storage, read_write> wake: array<atomic<u32>>;

// True for a kinematic body with any nonzero velocity component.
fn is_moving_kinematic(body: u32) -> bool {
    let v = velocities[body];
    let still = all(v.linear.xyz == vec3<f32>(0.0)) && all(v.angular.xyz == vec3<f32>(0.0));
    return awake_bodies[body].kind == BODY_KINEMATIC && !still;
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let k = thread_index(thread);
    if k >= work.count {
        return;
    }
    let m = manifolds[k];
    if m.len == 0u {
        return;
    }
    let label_a = island[m.body_a];
    let label_b = island[m.body_b];
    if label_a != AWAKE {
        atomicStore(&wake[label_a], 1u);
    }
    if label_b != AWAKE {
        atomicStore(&wake[label_b], 1u);
    }
    if is_moving_kinematic(m.body_a) || is_moving_kinematic(m.body_b) {
        rest_time[m.body_a] = 0.0;
        rest_time[m.body_b] = 0.0;
    }
}
