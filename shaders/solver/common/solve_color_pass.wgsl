// requires: common/indexing.wgsl solver/common/constraint_access.wgsl solver/common/body_slot.wgsl
// The body of solve_color and solve_color_immediate, which differ only in where the pass's
// ColorPass comes from (a uniform bound per color, or immediate data set per dispatch): one
// thread per constraint of one graph color (ColorPass.color) applies the pass chosen by the
// PASS override (warm start, biased solve, relax or restitution). A color's constraints are
// the slots color_offsets[color]..color_offsets[color + 1] (constraint_store.wgsl).
// Constraints of one color share no dynamic body, so they run at the same time and the
// result does not depend on their order; the overflow set runs in one thread, in order.
//
// With ColorPass.tail set, one thread visits every constraint of the colors from
// ColorPass.color to the last graph color, color after color, and then the overflow set: the
// host dispatches colors one by one only as far as a recent step used them, and the tail
// takes whatever lies beyond (usually nothing but the overflow set). Each constraint is
// visited by the same function with the same inputs and colors follow each other in the same
// order, so the bits do not depend on where the tail starts. The tail is the pass's pipeline
// with another ColorPass, not a pipeline of its own: on lavapipe, a second pipeline for it
// made the wide path's steps take seconds and its memory grow by hundreds of MB a step
// (docs/gpu-solver.md). One thread keeps the kernel free of barriers.
//
// Expects the including kernel to declare: color_offsets: array<u32> (storage, read), the
// override PASS: u32, and what constraint_access.wgsl expects.

// Every constraint slot from color `first`'s first to the overflow set's last, in order, in
// the calling thread: the colors one after another, then the overflow set (slots are laid
// out by color, the overflow set last).
fn visit_in_order(first: u32) {
    for (var k = color_offsets[first]; k < color_offsets[OVERFLOW_COLOR + 1u]; k++) {
        visit_constraint(k, PASS);
    }
}

// Thread `t` of the dispatch for `pass_color`.
fn solve_color_pass(thread: Thread, pass_color: ColorPass) {
    let t = linear_group(thread.workgroup, thread.groups) * COLOR_PASS_WORKGROUP_SIZE + thread.local;
    let color = pass_color.color;
    if pass_color.tail != 0u || color == OVERFLOW_COLOR {
        if t == 0u {
            visit_in_order(color);
        }
        return;
    }
    let begin = color_offsets[color];
    let end = color_offsets[color + 1u];
    if begin + t < end {
        visit_constraint(begin + t, PASS);
    }
}
