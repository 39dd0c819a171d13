// requires: common/layout.wgsl
// The sweep's pair test and its long boxes, shared by gather_sweep_boxes, sweep_pairs and
// long_pairs.
//
// A box longer on the sweep axis than `params.long_extent` (a floor under a pile, a wall
// along it) would make the thread that sweeps it scan every box it spans, one after the
// other: one thread doing the work of the whole pile while the rest of the device waits.
// gather_sweep_boxes lists such boxes (at most MAX_LONG_BOXES, by sorted position); while
// the list holds them all, sweep_pairs leaves them out, as sweepers and as candidates, and
// long_pairs tests each of them against every box, one thread per box. With more long boxes
// than the list holds, none is long and the sweep does everything. The pair set is the same
// either way (the pair sort then fixes the order).

// Entries of the long box list (crates/tumble-gpu/src/constants.rs).
override MAX_LONG_BOXES: u32;

// `long_boxes[0]` counts the boxes gather_sweep_boxes found long (past the list's length
// too); `long_boxes[1 + k]` is the sorted position of the k-th it listed.
fn long_boxes_listed(count: u32) -> bool {
    return count <= MAX_LONG_BOXES;
}

// Whether box `b` is long, given that the list holds every long box (`listed`).
fn is_long(b: GpuSweepBox, long_extent: f32, listed: bool) -> bool {
    return listed && b.hi_0 - b.lo_0 > long_extent;
}

// Whether two boxes overlap on the two axes after the sweep axis (closed intervals, so
// touching boxes pair, as on the CPU).
fn overlap_12(a: GpuSweepBox, b: GpuSweepBox) -> bool {
    return b.lo_1 <= a.hi_1 && a.lo_1 <= b.hi_1 && b.lo_2 <= a.hi_2 && a.lo_2 <= b.hi_2;
}

// Whether both boxes are static (such pairs are never formed).
fn both_static(a: GpuSweepBox, b: GpuSweepBox) -> bool {
    return (a.flags & b.flags & BODY_STATIC) != 0u;
}
