// requires: solver/common/coloring.wgsl
// The coloring rounds, the per-color counts and the stable order by color, run by a single
// workgroup (used by color_finish after the wide first round, and by solve_fused for all of it).
//
// Expects, besides what coloring.wgsl expects: color_scratch: array<u32> (read_write, two lists
// of up to n constraint indices), color_offsets: array<u32> (read_write, GRAPH_COLOR_COUNT + 2
// entries: color c is color_order[offsets[c]..offsets[c + 1]], the overflow set last).

// Lengths of the two undecided lists (appended with atomics; order does not matter).
var<workgroup> list_length: array<atomic<u32>, 2>;
// A value thread 0 publishes to the whole workgroup through workgroupUniformLoad.
var<workgroup> shared_value: u32;
// Constraints per color (overflow last).
var<workgroup> color_counts: array<atomic<u32>, GRAPH_COLOR_COUNT + 1u>;

// A barrier for both storage and workgroup memory: the single-workgroup stages communicate
// through both.
fn sync_workgroup() {
    storageBarrier();
    workgroupBarrier();
}

// Thread 0's `value`, seen by every thread as a uniform value.
fn publish(local: u32, value: u32) -> u32 {
    workgroupBarrier();
    if local == 0u {
        shared_value = value;
    }
    return workgroupUniformLoad(&shared_value);
}

// Rounds first_round..COLOR_ROUNDS over the undecided constraints among the first n; the ones
// still undecided after the last round go to the overflow set. With first_round = 0 every
// constraint starts undecided; otherwise the claims of the previous round are withdrawn first.
fn color_rounds_in_workgroup(local: u32, n: u32, first_round: u32) {
    if local == 0u {
        atomicStore(&list_length[0], 0u);
        atomicStore(&list_length[1], 0u);
    }
    workgroupBarrier();
    for (var i = local; i < n; i += WORKGROUP_SIZE) {
        if first_round == 0u {
            color_state[i] = ColorSlot(NO_COLOR, NO_COLOR);
        } else {
            color_clear(i);
        }
        if color_state[i].color == NO_COLOR {
            color_scratch[atomicAdd(&list_length[0], 1u)] = i;
        }
    }
    sync_workgroup();
    var current = 0u;
    for (var round = first_round; round < COLOR_ROUNDS; round++) {
        let count = publish(local, atomicLoad(&list_length[current]));
        if count == 0u {
            break;
        }
        let list = current * n;
        let next = (1u - current) * n;
        if local == 0u {
            atomicStore(&list_length[1u - current], 0u);
        }
        for (var k = local; k < count; k += WORKGROUP_SIZE) {
            color_propose(color_scratch[list + k], round);
        }
        sync_workgroup();
        for (var k = local; k < count; k += WORKGROUP_SIZE) {
            let i = color_scratch[list + k];
            if color_resolve(i) {
                color_scratch[next + atomicAdd(&list_length[1u - current], 1u)] = i;
            }
        }
        sync_workgroup();
        for (var k = local; k < count; k += WORKGROUP_SIZE) {
            color_clear(color_scratch[list + k]);
        }
        sync_workgroup();
        current = 1u - current;
    }
    let left = publish(local, atomicLoad(&list_length[current]));
    for (var k = local; k < left; k += WORKGROUP_SIZE) {
        color_state[color_scratch[current * n + k]].color = OVERFLOW_COLOR;
    }
    sync_workgroup();
}

// Counts the constraints of each color and writes color_offsets; returns (to every thread)
// one past the highest color in use, overflow excluded.
fn count_colors_in_workgroup(local: u32, n: u32) -> u32 {
    for (var c = local; c <= GRAPH_COLOR_COUNT; c += WORKGROUP_SIZE) {
        atomicStore(&color_counts[c], 0u);
    }
    workgroupBarrier();
    for (var i = local; i < n; i += WORKGROUP_SIZE) {
        let color = color_state[i].color;
        if color <= OVERFLOW_COLOR {
            atomicAdd(&color_counts[color], 1u);
        }
    }
    workgroupBarrier();
    var used = 0u;
    if local == 0u {
        var offset = 0u;
        for (var c = 0u; c <= GRAPH_COLOR_COUNT; c++) {
            color_offsets[c] = offset;
            let count = atomicLoad(&color_counts[c]);
            offset += count;
            if count > 0u && c < GRAPH_COLOR_COUNT {
                used = c + 1u;
            }
        }
        color_offsets[GRAPH_COLOR_COUNT + 1u] = offset;
    }
    sync_workgroup();
    return publish(local, used);
}
