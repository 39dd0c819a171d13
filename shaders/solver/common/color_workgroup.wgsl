// requires: solver/common/coloring.wgsl
// The coloring rounds and the per-color counts, run by a single workgroup (color_finish runs
// the rounds after the wide first round; solve_fused runs all of it).
//
// Expects, besides what coloring.wgsl expects: color_scratch: array<u32> (read_write, two lists
// of up to n constraint indices).

// Lengths of the two undecided lists (appended with atomics; order does not matter).
var<workgroup> list_length: array<atomic<u32>, 2>;
// A value thread 0 publishes to the whole workgroup through workgroupUniformLoad.
var<workgroup> shared_value: u32;

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

// Lists every one of the n constraints from `base` on as undecided (list 0) and clears its
// slot: the start of a coloring from round 0, with nothing seeded (solve_fused, and
// solve_worlds for one world's constraints). The two lists of a range start at 2 * base in
// color_scratch (ranges do not overlap: 2 * base + 2 * n <= 2 * capacity).
fn list_all_in_workgroup(local: u32, base: u32, n: u32) {
    if local == 0u {
        atomicStore(&list_length[0], n);
        atomicStore(&list_length[1], 0u);
    }
    for (var k = local; k < n; k += WORKGROUP_SIZE) {
        color_state[base + k] = ColorSlot(NO_COLOR, NO_COLOR);
        color_scratch[2u * base + k] = base + k;
    }
    sync_workgroup();
}

// Takes list 0 as the `count` undecided constraints another kernel wrote (color_withdraw,
// after the wide first round).
fn take_list_in_workgroup(local: u32, count: u32) {
    if local == 0u {
        atomicStore(&list_length[0], count);
        atomicStore(&list_length[1], 0u);
    }
    sync_workgroup();
}

// Rounds first_round..COLOR_ROUNDS over the undecided constraints in list 0 (of the n from
// `base` on, the lists at 2 * base), with no claim standing; the ones still undecided after
// the last round go to the overflow set. The lists' order does not matter: a round's outcome
// depends only on the set.
fn color_rounds_in_workgroup(local: u32, base: u32, n: u32, first_round: u32) {
    var current = 0u;
    for (var round = first_round; round < COLOR_ROUNDS; round++) {
        let count = publish(local, atomicLoad(&list_length[current]));
        if count == 0u {
            break;
        }
        let list = 2u * base + current * n;
        let next = 2u * base + (1u - current) * n;
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
        color_state[color_scratch[2u * base + current * n + k]].color = OVERFLOW_COLOR;
    }
    sync_workgroup();
}
