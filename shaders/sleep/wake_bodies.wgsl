// requires: common/indexing.wgsl sleep/common/sleep_constants.wgsl
// wake_bodies: one thread goes through the bodies the host touched since the last step (a
// pose, a velocity or an impulse set, or an explicit wake), in queue order: each body's rest
// time starts over, and a sleeping body's island is flagged to wake in wake_islands.

// `array<u32>`: the bodies touched by the host since the last step.
@group(0) @binding(0) var<storage, read> queued: array<u32>;
// `array<u32>`: each body's island label, or `AWAKE`.
@group(0) @binding(1) var<storage, read> island: array<u32>;
// `array<f32>`: rest times, reset for the queued bodies.
@group(0) @binding(2) var<storage, read_write> rest_time: array<f32>;
// `array<u32>`: wake flags by island label, set.
@group(0) @binding(3) var<storage, read_write> wake: array<u32>;

@compute @workgroup_size(1)
fn main() {
    for (var k = 0u; k < arrayLength(&queued); k++) {
        let body = queued[k];
        rest_time[body] = 0.0;
        let label = island[body];
        if label != AWAKE {
            wake[label] = 1u;
        }
    }
}
