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

// The index of the world box `b`'s body belongs to (bodies of different worlds never pair).
fn box_world(b: GpuSweepBox) -> u32 {
    return b.flags >> BODY_WORLD_SHIFT;
}

// Flips all bits of negative floats and only the sign bit of positive ones, so that
// unsigned comparison of keys orders like float comparison. -0.0 first becomes +0.0: the
// two compare equal as floats and must get one key.
fn order_key(x: f32) -> u32 {
    var bits = bitcast<u32>(x);
    if bits == 0x80000000u {
        bits = 0u;
    }
    if (bits & 0x80000000u) != 0u {
        return ~bits;
    }
    return bits | 0x80000000u;
}

// The sort key of a bound `x` on the sweep axis in world `world`: the world's `world_bits`
// bits lead, then the top of `order_key(x)`. With one world (`world_bits` 0) it is
// `order_key(x)` itself; with more, bounds closer than the dropped bits share a key, which
// is why the sweep also tests the lower side of the sweep axis (sweep_pairs.wgsl).
fn sweep_key(world: u32, x: f32, world_bits: u32) -> u32 {
    if world_bits == 0u {
        return order_key(x);
    }
    return (world << (32u - world_bits)) | (order_key(x) >> world_bits);
}
