// wake_islands: one thread per body. A sleeping body whose island was flagged (touched by an
// awake body last step, or by the host) wakes: its label turns AWAKE, its rest time starts
// over, and its solver data and shape flags are restored from the awake copy, so the step
// that follows moves it again.

@group(0) @binding(0) var<uniform> params: SleepParams;
@group(0) @binding(1) var<storage, read> wake: array<u32>;
@group(0) @binding(2) var<storage, read> awake_bodies: array<GpuBody>;
@group(0) @binding(3) var<storage, read_write> island: array<u32>;
@group(0) @binding(4) var<storage, read_write> rest_time: array<f32>;
@group(0) @binding(5) var<storage, read_write> bodies: array<GpuBody>;
@group(0) @binding(6) var<storage, read_write> shapes: array<GpuShape>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let i = linear_index(workgroup, groups, local);
    if i >= params.body_count {
        return;
    }
    let label = island[i];
    if label == AWAKE || wake[label] == 0u {
        return;
    }
    island[i] = AWAKE;
    rest_time[i] = 0.0;
    bodies[i] = awake_bodies[i];
    // Only dynamic bodies sleep, and a dynamic body's shape is never static.
    shapes[i].flags = shapes[i].flags & ~BODY_STATIC;
}
