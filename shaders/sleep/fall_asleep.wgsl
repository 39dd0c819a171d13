// requires: common/indexing.wgsl sleep/common/sleep_constants.wgsl
// fall_asleep: one thread per body. A linkable body whose island's shortest rest time has
// reached TIME_TO_SLEEP falls asleep with its island: it takes the island's label, its
// velocity becomes zero, and it turns into a fixed body for the solver and a static shape
// for the broad phase, so pairs between it and other sleeping or fixed bodies are never
// formed and the solver meets it as an immovable obstacle. Nothing falls asleep in a step
// whose island search did not finish.

@group(0) @binding(0) var<uniform> params: SleepParams;
// `array<u32>`, one entry: nonzero when the island search did not finish.
@group(0) @binding(1) var<storage, read> unfinished: array<u32>;
// `array<GpuBody>`: every body as uploaded.
@group(0) @binding(2) var<storage, read> awake_bodies: array<GpuBody>;
// `array<u32>`: the finished search labels.
@group(0) @binding(3) var<storage, read> labels: array<u32>;
// `array<u32>`: shortest rest time bits by label.
@group(0) @binding(4) var<storage, read> shortest_rest: array<u32>;
// `array<u32>`: island labels, set for the bodies falling asleep.
@group(0) @binding(5) var<storage, read_write> island: array<u32>;
// `array<GpuVelocity>`: zeroed for the bodies falling asleep.
@group(0) @binding(6) var<storage, read_write> velocities: array<GpuVelocity>;
// `array<GpuBody>`: the solver's bodies, made fixed for the bodies falling asleep.
@group(0) @binding(7) var<storage, read_write> bodies: array<GpuBody>;
// `array<GpuShape>`: the collision shapes, flagged static for the bodies falling asleep.
@group(0) @binding(8) var<storage, read_write> shapes: array<GpuShape>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= params.body_count || unfinished[0] != 0u {
        return;
    }
    let awake = awake_bodies[i];
    if !is_linkable(awake.kind, island[i]) {
        return;
    }
    let label = labels[i];
    if bitcast<f32>(shortest_rest[label]) < TIME_TO_SLEEP {
        return;
    }
    island[i] = label;
    velocities[i] = GpuVelocity(vec4<f32>(0.0), vec4<f32>(0.0));
    var fixed = awake;
    fixed.kind = BODY_FIXED;
    fixed.inverse_inertia = vec4<f32>(0.0);
    fixed.inertia = vec4<f32>(0.0);
    bodies[i] = fixed;
    shapes[i].flags = shapes[i].flags | BODY_STATIC;
}
