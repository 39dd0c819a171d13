// requires: common/indexing.wgsl solver/common/color_bindings.wgsl
// color_propose: the first coloring round's proposals, one thread per constraint. Round 0
// proposes last step's color where the pair had a manifold, so a scene that changed little
// is colored by this round alone; color_resolve keeps the proposals whose claims held and
// color_withdraw and color_finish run the remaining rounds.

// The bindings are color_bindings.wgsl's.

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= contact_work.count {
        return;
    }
    color_propose(i, 0u);
}
