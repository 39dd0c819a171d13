// requires: common/indexing.wgsl solver/common/color_bindings.wgsl solver/common/color_workgroup.wgsl
// color_finish: a single workgroup runs the coloring rounds after the first over the
// constraints color_withdraw left undecided (few, after the seeded first round) and sends
// what is left after the last round to the overflow set. Everything over all constraints
// runs wide, before (color_propose, color_resolve, color_withdraw) and after (color_count).

// The bindings are color_bindings.wgsl's.

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(@builtin(local_invocation_index) local: u32) {
    let undecided = publish(local, atomicLoad(&color_tally[TALLY_UNDECIDED]));
    take_list_in_workgroup(local, undecided);
    // Round 0 ran wide, in color_propose and color_resolve.
    color_rounds_in_workgroup(local, 0u, contact_work.count, 1u);
}
