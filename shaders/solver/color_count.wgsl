// requires: common/indexing.wgsl common/solver_types.wgsl solver/common/solver_constants.wgsl
// color_count: one thread per constraint, once every color is decided: counts the constraints
// of each color (per workgroup, then one atomic add per color and workgroup into the tally;
// sums do not depend on the order of the adds) and lays out the (color, index) keys of the
// stable radix sort that produces the constraint order by color.

// The contacts' `WorkList`.
@group(0) @binding(0) var<storage, read> contact_work: WorkList;
// This step's `array<ColorSlot>`, every color decided.
@group(0) @binding(1) var<storage, read> color_state: array<ColorSlot>;
// The tally, whose per-color counts this adds to.
@group(0) @binding(2) var<storage, read_write> color_tally: array<atomic<u32>>;
// Output: sort keys (the colors).
@group(0) @binding(3) var<storage, read_write> sort_keys: array<u32>;
// Output: sort values (the constraint indices).
@group(0) @binding(4) var<storage, read_write> sort_values: array<u32>;

// This workgroup's constraints per color (overflow last); zero at the start (the pipelines
// are built with zero_initialize_workgroup_memory).
var<workgroup> counts: array<atomic<u32>, GRAPH_COLOR_COUNT + 1u>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let i = thread_index(thread);
    if i < contact_work.count {
        let color = color_state[i].color;
        if color <= OVERFLOW_COLOR {
            atomicAdd(&counts[color], 1u);
        }
        sort_keys[i] = color;
        sort_values[i] = i;
    }
    workgroupBarrier();
    if thread.local <= OVERFLOW_COLOR {
        let count = atomicLoad(&counts[thread.local]);
        if count > 0u {
            atomicAdd(&color_tally[TALLY_COUNTS + thread.local], count);
        }
    }
}
