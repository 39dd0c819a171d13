// requires: common/indexing.wgsl solver/common/color_bindings.wgsl
// color_resolve: the first coloring round's decisions, one thread per constraint: a
// constraint whose (body, color) claims all hold keeps its color and marks it used at its
// dynamic bodies; the others stay undecided for color_withdraw and color_finish.

// The bindings are color_bindings.wgsl's.

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i >= contact_work.count {
        return;
    }
    _ = color_resolve(i);
}
