// requires: common/indexing.wgsl sleep/common/sleep_constants.wgsl
// update_rest: one thread per body, after the solver. An awake dynamic body's rest time
// grows by dt while it is below both sleep tolerances and starts over otherwise; other
// bodies rest for no time (a sleeping body's is frozen until it wakes). Every body also
// starts this step's island search as its own island (both label buffers), with no rest
// time reported for the island it names. It counts the bodies whose rest reached
// TIME_TO_SLEEP: with none, no island can fall asleep, and plan_search skips the search.

@group(0) @binding(0) var<uniform> params: SleepParams;
// `array<GpuBody>`: every body as uploaded (its real kind).
@group(0) @binding(1) var<storage, read> awake_bodies: array<GpuBody>;
// `array<GpuVelocity>`: the step's final velocities.
@group(0) @binding(2) var<storage, read> velocities: array<GpuVelocity>;
// `array<u32>`: island labels.
@group(0) @binding(3) var<storage, read> island: array<u32>;
// `array<f32>`: rest times, updated.
@group(0) @binding(4) var<storage, read_write> rest_time: array<f32>;
// `array<u32>`: search labels, each body its own.
@group(0) @binding(5) var<storage, read_write> labels: array<u32>;
// `array<u32>`: the first round's copy of them.
@group(0) @binding(6) var<storage, read_write> next_labels: array<u32>;
// `array<u32>`: shortest rest time bits by label, reset to `REST_UNSET`.
@group(0) @binding(7) var<storage, read_write> shortest_rest: array<u32>;
// One `atomic<u32>`: bodies whose rest reached `TIME_TO_SLEEP`, counted up.
@group(0) @binding(8) var<storage, read_write> ready: array<atomic<u32>>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= params.body_count {
        return;
    }
    labels[i] = i;
    next_labels[i] = i;
    shortest_rest[i] = REST_UNSET;
    if awake_bodies[i].kind != BODY_DYNAMIC {
        rest_time[i] = 0.0;
        return;
    }
    if island[i] != AWAKE {
        return;
    }
    let v = velocities[i];
    let resting = length(v.linear.xyz) < LINEAR_SLEEP_TOLERANCE
        && length(v.angular.xyz) < ANGULAR_SLEEP_TOLERANCE;
    let rest = select(0.0, rest_time[i] + params.dt, resting);
    rest_time[i] = rest;
    if rest >= TIME_TO_SLEEP {
        atomicAdd(&ready[0], 1u);
    }
}
