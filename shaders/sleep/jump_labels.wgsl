// requires: common/indexing.wgsl sleep/common/sleep_constants.wgsl
// jump_labels: one thread per body, the second half of a round of the island search. Each
// body's label becomes its label's label (pointer jumping: a chain of hooks halves in length
// each round). It reads `next_labels` only and writes the result twice, into `labels` (read
// by the next hook) and `spare` (the copy the next hook lowers), so no thread reads what
// another writes.

@group(0) @binding(0) var<uniform> params: SleepParams;
// `array<u32>`: the labels after this round's hooks.
@group(0) @binding(1) var<storage, read> next_labels: array<u32>;
// `array<u32>`: the round's result.
@group(0) @binding(2) var<storage, read_write> labels: array<u32>;
// `array<u32>`: the same result, the copy the next round hooks into.
@group(0) @binding(3) var<storage, read_write> spare: array<u32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= params.body_count {
        return;
    }
    let jumped = next_labels[next_labels[i]];
    labels[i] = jumped;
    spare[i] = jumped;
}
