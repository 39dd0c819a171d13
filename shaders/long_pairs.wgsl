// requires: common/indexing.wgsl common/pair_output.wgsl
// long_pairs: one thread per sorted position tests its box against every long box that
// gather_sweep_boxes listed (common/sweep.wgsl) and appends each overlapping pair, as
// sweep_pairs does, through the same counter. A pair of two long boxes is appended by the
// thread of the one with the larger body index only. Nothing happens when the list could not
// hold every long box (the sweep did all the pairs then).

// The bindings are common/pair_output.wgsl's.

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let q = thread_index(thread);
    let count = long_boxes[0];
    if q >= params.body_count || count == 0u || !long_boxes_listed(count) {
        return;
    }
    let me = sweep_boxes[q];
    let me_long = is_long(me, params.long_extent, true);
    for (var k = 0u; k < count; k++) {
        let p = long_boxes[1u + k];
        if p == q {
            continue;
        }
        let long_box = sweep_boxes[p];
        if me_long && me.body < long_box.body {
            continue;
        }
        let overlaps = long_box.lo_0 <= me.hi_0 && me.lo_0 <= long_box.hi_0
            && overlap_12(me, long_box);
        if !overlaps || box_world(me) != box_world(long_box) || both_static(me, long_box)
            || !groups_interact(me.body, long_box.body) {
            continue;
        }
        append_pair(me, long_box);
    }
}
