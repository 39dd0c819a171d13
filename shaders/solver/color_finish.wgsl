// requires: common/indexing.wgsl solver/common/color_bindings.wgsl solver/common/color_workgroup.wgsl
// color_finish: a single workgroup withdraws the first round's claims, runs the remaining
// coloring rounds over the constraints still undecided (few, after the seeded first round),
// sends what is left to the overflow set, counts each color, writes the per-color offsets and
// the indirect dispatch size of every per-color pass, and lays out (color, index) keys for
// the stable radix sort that produces the constraint order by color.

// Bindings 0 to 6 are color_bindings.wgsl's.
@group(0) @binding(7) var<storage, read_write> color_scratch: array<u32>;
@group(0) @binding(8) var<storage, read_write> color_offsets: array<u32>;
@group(0) @binding(9) var<storage, read_write> color_args: array<DispatchArgs>;
@group(0) @binding(10) var<storage, read_write> sort_keys: array<u32>;
@group(0) @binding(11) var<storage, read_write> sort_values: array<u32>;

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

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(@builtin(local_invocation_index) local: u32) {
    let n = contact_work.count;
    // Round 0 ran wide, in color_propose and color_resolve.
    color_rounds_in_workgroup(local, n, 1u);
    _ = count_colors_in_workgroup(local, n);
    if local <= GRAPH_COLOR_COUNT {
        let count = color_offsets[local + 1u] - color_offsets[local];
        if local == OVERFLOW_COLOR {
            // The overflow set runs in one thread, in order.
            color_args[local] = DispatchArgs(min(count, 1u), 1u, 1u, 0u);
        } else {
            color_args[local] = dispatch_for(count);
        }
    }
    for (var i = local; i < n; i += WORKGROUP_SIZE) {
        sort_keys[i] = color_state[i].color;
        sort_values[i] = i;
    }
}
