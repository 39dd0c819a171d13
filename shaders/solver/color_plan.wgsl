// requires: common/layout.wgsl solver/common/solver_constants.wgsl
// color_plan: one thread turns the tally's per-color counts into the color offsets (color c
// is color_order[offsets[c]..offsets[c + 1]], the overflow set last) and the indirect
// dispatch size of every per-color pass.

// The tally with every color counted.
@group(0) @binding(0) var<storage, read> color_tally: array<u32>;
// Output: `COLOR_OFFSETS_LEN` offsets.
@group(0) @binding(1) var<storage, read_write> color_offsets: array<u32>;
// Output: `array<DispatchArgs>`, one per color slot.
@group(0) @binding(2) var<storage, read_write> color_args: array<DispatchArgs>;

// Workgroups of a per-color pass for one thread per item, folded past the per-dimension limit
// as plan_dispatch does.
fn dispatch_for(items: u32) -> DispatchArgs {
    let groups = (items + COLOR_PASS_WORKGROUP_SIZE - 1u) / COLOR_PASS_WORKGROUP_SIZE;
    if groups > MAX_WORKGROUPS_PER_DIMENSION {
        return DispatchArgs(
            MAX_WORKGROUPS_PER_DIMENSION,
            (groups + MAX_WORKGROUPS_PER_DIMENSION - 1u) / MAX_WORKGROUPS_PER_DIMENSION,
            1u,
            0u,
        );
    }
    return DispatchArgs(groups, 1u, 1u, 0u);
}

@compute @workgroup_size(1)
fn main() {
    var offset = 0u;
    for (var c = 0u; c <= OVERFLOW_COLOR; c++) {
        color_offsets[c] = offset;
        let count = color_tally[TALLY_COUNTS + c];
        offset += count;
        if c == OVERFLOW_COLOR {
            // The overflow set runs in one thread, in order.
            color_args[c] = DispatchArgs(min(count, 1u), 1u, 1u, 0u);
        } else {
            color_args[c] = dispatch_for(count);
        }
    }
    color_offsets[OVERFLOW_COLOR + 1u] = offset;
}
