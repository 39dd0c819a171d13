// requires: common/solver_types.wgsl solver/common/solver_constants.wgsl
// Graph coloring of constraints in rounds (Jones-Plassmann-Luby with speculative colors):
// in a round every undecided constraint proposes the lowest color free at both of its dynamic
// bodies (in round 0: last step's color if it is free), and claims (body, color) for each
// dynamic body with its priority through atomicMax; a constraint whose claims all hold keeps
// its color, the others try again next round. Priorities are distinct (a bijective hash of
// the constraint index), so at most one constraint wins a (body, color) per round, and every
// round decides at least the highest-priority undecided constraint. Nothing depends on the
// order in which threads run, which is what makes the colors (and the solve) deterministic.
//
// Expects the including kernel to declare:
//   params: SolverParams (uniform), manifolds: array<GpuManifold>, bodies: array<GpuBody>,
//   previous_colors: array<ColorSlot> (last step's), color_state: array<ColorSlot> (read_write),
//   color_marks: array<atomic<u32>> (read_write): per body its used-color mask, then per
//   (body, color) the highest priority claiming it; all zero between rounds;
//   fn constraint_rank(i: u32) -> u32: constraint i's index among its world's.

// A bijective 32-bit integer hash (Wellons' "lowbias32": xorshifts and odd multipliers are
// each invertible), so distinct constraints get distinct priorities.
fn hash_u32(x_in: u32) -> u32 {
    var x = x_in;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

// Constraint i's priority: nonzero (hash(0) = 0 is never used) and distinct within its
// world. It hashes the constraint's rank in its world (`constraint_rank`, defined by the
// including bindings: the index itself when the step holds one world), so a world colors
// its constraints alike whether it is stepped alone or in a batch with others.
fn color_priority(i: u32) -> u32 {
    return hash_u32(constraint_rank(i) + 1u);
}

fn all_colors_mask() -> u32 {
    return select((1u << GRAPH_COLOR_COUNT) - 1u, 0xffffffffu, GRAPH_COLOR_COUNT >= 32u);
}

fn claim_slot(body: u32, color: u32) -> u32 {
    return params.body_count + body * GRAPH_COLOR_COUNT + color;
}

fn is_dynamic_body(body: u32) -> bool {
    return bodies[body].kind == BODY_DYNAMIC;
}

// Round `round` proposal of undecided constraint i (writes its whole ColorSlot). A manifold
// without points is no constraint: it takes EMPTY_COLOR and claims nothing.
fn color_propose(i: u32, round: u32) {
    if manifolds[i].len == 0u {
        color_state[i] = ColorSlot(EMPTY_COLOR, NO_COLOR);
        return;
    }
    let a = manifolds[i].body_a;
    let b = manifolds[i].body_b;
    let dynamic_a = is_dynamic_body(a);
    let dynamic_b = is_dynamic_body(b);
    var taken = 0u;
    if dynamic_a {
        taken |= atomicLoad(&color_marks[a]);
    }
    if dynamic_b {
        taken |= atomicLoad(&color_marks[b]);
    }
    let free = ~taken & all_colors_mask();
    if free == 0u {
        color_state[i] = ColorSlot(OVERFLOW_COLOR, NO_COLOR);
        return;
    }
    var color = firstTrailingBit(free);
    let previous = manifolds[i].previous;
    if round == 0u && previous != NO_PREVIOUS && previous < arrayLength(&previous_colors) {
        let seed = previous_colors[previous].color;
        if seed < GRAPH_COLOR_COUNT && ((free >> seed) & 1u) != 0u {
            color = seed;
        }
    }
    color_state[i] = ColorSlot(NO_COLOR, color);
    let priority = color_priority(i);
    if dynamic_a {
        atomicMax(&color_marks[claim_slot(a, color)], priority);
    }
    if dynamic_b {
        atomicMax(&color_marks[claim_slot(b, color)], priority);
    }
}

// Keeps constraint i's proposal if all its claims held; true when it is still undecided.
fn color_resolve(i: u32) -> bool {
    let color = color_state[i].proposal;
    if color == NO_COLOR {
        // Overflowed during the proposal: decided.
        return false;
    }
    let a = manifolds[i].body_a;
    let b = manifolds[i].body_b;
    let dynamic_a = is_dynamic_body(a);
    let dynamic_b = is_dynamic_body(b);
    let priority = color_priority(i);
    var won = true;
    if dynamic_a && atomicLoad(&color_marks[claim_slot(a, color)]) != priority {
        won = false;
    }
    if dynamic_b && atomicLoad(&color_marks[claim_slot(b, color)]) != priority {
        won = false;
    }
    if !won {
        return true;
    }
    color_state[i].color = color;
    if dynamic_a {
        atomicOr(&color_marks[a], 1u << color);
    }
    if dynamic_b {
        atomicOr(&color_marks[b], 1u << color);
    }
    return false;
}

// Withdraws constraint i's claims after a round, so the next round starts from zero.
fn color_clear(i: u32) {
    let color = color_state[i].proposal;
    if color == NO_COLOR {
        return;
    }
    let a = manifolds[i].body_a;
    let b = manifolds[i].body_b;
    if is_dynamic_body(a) {
        atomicStore(&color_marks[claim_slot(a, color)], 0u);
    }
    if is_dynamic_body(b) {
        atomicStore(&color_marks[claim_slot(b, color)], 0u);
    }
    color_state[i].proposal = NO_COLOR;
}
