// requires: common/indexing.wgsl solver/common/color_bindings.wgsl
// color_withdraw: one thread per constraint withdraws the first round's claims (so the next
// round starts with none standing) and appends each constraint still undecided to the list
// color_finish continues from. The list's order depends on thread timing; what color_finish
// computes from it does not (coloring.wgsl).

// The bindings are color_bindings.wgsl's.

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= contact_work.count {
        return;
    }
    color_clear(i);
    if color_state[i].color == NO_COLOR {
        color_scratch[atomicAdd(&color_tally[TALLY_UNDECIDED], 1u)] = i;
    }
}
