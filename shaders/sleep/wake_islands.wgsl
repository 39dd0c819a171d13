// requires: common/indexing.wgsl sleep/common/sleep_constants.wgsl
// wake_islands: one thread per body. A sleeping body whose island was flagged (touched by an
// awake body last step, or by the host) wakes: its label turns AWAKE, its rest time starts
// over, and its solver data and shape flags are restored from the awake copy, so the step
// that follows moves it again.
//
// It also counts the bodies the step will move (every body not fixed once the islands have
// woken: awake dynamic bodies and kinematic ones) into `moving[0]`, cleared by the host
// before the dispatch: a step that moves none, forms no contact and had none before changes
// nothing, and the host skips the steps after it until something changes (GpuWorld's idle
// steps). The count is exact whatever the thread order.

@group(0) @binding(0) var<uniform> params: SleepParams;
// `array<u32>`: wake flags by island label.
@group(0) @binding(1) var<storage, read> wake: array<u32>;
// `array<GpuBody>`: every body as uploaded (awake).
@group(0) @binding(2) var<storage, read> awake_bodies: array<GpuBody>;
// `array<u32>`: island labels, `AWAKE` for the bodies woken.
@group(0) @binding(3) var<storage, read_write> island: array<u32>;
// `array<f32>`: rest times, reset for the bodies woken.
@group(0) @binding(4) var<storage, read_write> rest_time: array<f32>;
// `array<GpuBody>`: the solver's bodies, restored for the bodies woken.
@group(0) @binding(5) var<storage, read_write> bodies: array<GpuBody>;
// `array<GpuShape>`: the collision shapes, static flag cleared for the bodies woken.
@group(0) @binding(6) var<storage, read_write> shapes: array<GpuShape>;
// One `u32`, cleared before: the bodies the step moves (not fixed once woken) are added to it.
@group(0) @binding(7) var<storage, read_write> moving: array<atomic<u32>>;

// This workgroup's moving bodies, added to `moving` once.
var<workgroup> group_moving: atomic<u32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if thread.local == 0u {
        atomicStore(&group_moving, 0u);
    }
    workgroupBarrier();
    if i < params.body_count {
        var kind = bodies[i].kind;
        let label = island[i];
        if label != AWAKE && wake[label] != 0u {
            island[i] = AWAKE;
            rest_time[i] = 0.0;
            let body = awake_bodies[i];
            bodies[i] = body;
            kind = body.kind;
            // Only dynamic bodies sleep, and a dynamic body's shape is never static.
            shapes[i].flags = shapes[i].flags & ~BODY_STATIC;
        }
        if kind != BODY_FIXED {
            atomicAdd(&group_moving, 1u);
        }
    }
    workgroupBarrier();
    if thread.local == 0u {
        let count = atomicLoad(&group_moving);
        if count != 0u {
            atomicAdd(&moving[0], count);
        }
    }
}
