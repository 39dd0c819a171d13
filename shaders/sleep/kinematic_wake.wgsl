// requires: common/indexing.wgsl sleep/common/sleep_constants.wgsl
// kinematic_wake: one thread per body. A sleeping body whose AABB overlaps that of a moving
// kinematic body flags its island to wake at the start of the next step. The broad phase
// never pairs the two (a kinematic body and a sleeping one are both static to it, as a
// contact cannot move either), so this is how a moving platform or pusher reaches a sleeping
// island. The kinematic bodies are few: each thread loops over their list.

@group(0) @binding(0) var<uniform> params: SleepParams;
// `array<u32>`: the kinematic bodies.
@group(0) @binding(1) var<storage, read> kinematic: array<u32>;
// `array<GpuVelocity>`: the step's velocities.
@group(0) @binding(2) var<storage, read> velocities: array<GpuVelocity>;
// `array<GpuAabb>`: the step's AABBs.
@group(0) @binding(3) var<storage, read> aabbs: array<GpuAabb>;
// `array<u32>`: island labels.
@group(0) @binding(4) var<storage, read> island: array<u32>;
// `array<atomic<u32>>`: wake flags by island label, set.
@group(0) @binding(5) var<storage, read_write> wake: array<atomic<u32>>;

// True when the closed boxes overlap on every axis (touching counts, as in the sweep).
fn overlaps(a: GpuAabb, b: GpuAabb) -> bool {
    return all(a.min.xyz <= b.max.xyz) && all(b.min.xyz <= a.max.xyz);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= params.body_count {
        return;
    }
    let label = island[i];
    if label == AWAKE {
        return;
    }
    let mine = aabbs[i];
    for (var k = 0u; k < params.kinematic_count; k++) {
        let other = kinematic[k];
        let v = velocities[other];
        let still = all(v.linear.xyz == vec3<f32>(0.0)) && all(v.angular.xyz == vec3<f32>(0.0));
        if !still && overlaps(mine, aabbs[other]) {
            atomicStore(&wake[label], 1u);
            return;
        }
    }
}
