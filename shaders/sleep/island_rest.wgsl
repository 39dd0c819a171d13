// requires: common/indexing.wgsl sleep/common/sleep_constants.wgsl
// island_rest: one thread per body. Each linkable body reports its rest time to its island
// (named by its label) with atomicMin on the f32 bits: rest times are never negative, and
// non-negative floats order like their bit patterns, so the minimum of the bits is the bits
// of the minimum, in any thread order.

@group(0) @binding(0) var<uniform> params: SleepParams;
// `array<GpuBody>`: every body as uploaded.
@group(0) @binding(1) var<storage, read> awake_bodies: array<GpuBody>;
// `array<u32>`: island labels.
@group(0) @binding(2) var<storage, read> island: array<u32>;
// `array<u32>`: the finished search labels.
@group(0) @binding(3) var<storage, read> labels: array<u32>;
// `array<f32>`: rest times.
@group(0) @binding(4) var<storage, read> rest_time: array<f32>;
// `array<atomic<u32>>`: shortest rest time bits by label, lowered.
@group(0) @binding(5) var<storage, read_write> shortest_rest: array<atomic<u32>>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= params.body_count || !is_linkable(awake_bodies[i].kind, island[i]) {
        return;
    }
    atomicMin(&shortest_rest[labels[i]], bitcast<u32>(rest_time[i]));
}
