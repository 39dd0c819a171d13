// requires: common/indexing.wgsl solver/common/body_math.wgsl solver/common/body_slot.wgsl
// requires: solver/common/warm_start_body.wgsl
// solve_step: every substep of the wide path's solve in ONE dispatch. The per-color path
// dispatches each phase of a substep on its own (integrate velocities, the per-body warm start
// and the overflow set's, each graph color of each solve pass, integrate positions, each color
// of each relax pass), and a pyramid of 24 spends most of its solve in those ~50 dependent
// dispatches a substep, each a launch and a device-wide barrier of a few microseconds whatever
// its size (docs/gpu-solver.md). Here the phases of the whole step are one sequence of
// chunks handed out by a ticket counter: a workgroup takes the next ticket, waits until every
// chunk of the phases before its chunk's phase is done (a second counter), runs its chunk and
// counts it done. The phases follow each other exactly as the dispatches did, so the result is
// the per-color path's: each constraint and body is visited by the same function with the same
// inputs, the constraints of one color share no dynamic body, and the overflow set runs in one
// thread, in order. (solve_color picks its pass with the PASS override where this kernel
// passes it at run time, so the two are different programs that a driver could round
// differently; lavapipe and NVIDIA's driver give the same bits, tests/tests/gpu_determinism.rs.)
//
// Why tickets and not a barrier across a fixed grid: a workgroup only ever waits for chunks
// whose tickets were taken before its own, by workgroups that were running when they took
// them, so the wait ends however many workgroups the device runs at once (one, on a CPU
// adapter, runs them all in turn); a grid barrier would hang wherever the grid does not fit on
// the device at once. The bodies, velocities and constraints that one workgroup writes and
// another reads within the dispatch are `@coherent`, and storageBarrier (a device-scope
// acquire-release barrier) separates a chunk's writes from its counter and the counter from
// the next phase's reads.

@group(0) @binding(0) var<uniform> params: SolverParams;
// Per-color offsets: color `c` is the constraint slots `offsets[c]..offsets[c + 1]`.
@group(0) @binding(1) var<storage, read> color_offsets: array<u32>;
@group(0) @binding(2) var<storage, read> bodies: array<GpuBody>;
// `array<GpuPose>` (start of step).
@group(0) @binding(3) var<storage, read> poses: array<GpuPose>;
// `array<GpuSolverBody>`, deltas updated.
@group(0) @binding(4) @coherent var<storage, read_write> solver_bodies: array<GpuSolverBody>;
// `array<GpuVelocity>`, updated.
@group(0) @binding(5) @coherent var<storage, read_write> velocities: array<GpuVelocity>;
// The constraint store (`GpuConstraint` rows, by slot), updated.
@group(0) @binding(6) @coherent var<storage, read_write> constraints: array<vec4<f32>>;
// The coloring's marks (warm_start_body.wgsl).
@group(0) @binding(7) var<storage, read> color_marks: array<u32>;
// [0]: the next ticket; [1]: chunks done (counted per thread on CPU adapters: see
// SOLVE_STEP_PER_THREAD_SYNC); [2]: set when a wait gave up (SOLVE_STEP_WAIT_LIMIT). All zero
// before the dispatch.
@group(0) @binding(8) var<storage, read_write> step_progress: array<atomic<u32>>;

// Phase kinds. A body's velocity integration and its warm start are one phase: both read
// and write that body's velocity only (warm_start_body.wgsl), so one thread doing the two in
// turn gives the bits of two phases, one after the other, and saves a dependent phase a
// substep.
const PHASE_VELOCITIES_AND_WARM: u32 = 0u;
const PHASE_COLOR: u32 = 2u;
const PHASE_POSITIONS: u32 = 3u;

struct Phase {
    kind: u32,
    // PASS_* of a color phase.
    pass_kind: u32,
    // The graph color of a color phase, or OVERFLOW_COLOR.
    color: u32,
}

// Phases of substep `s`: integrate velocities and the warm start per body, the overflow
// set's warm start, `iterations` solve sweeps of every color slot, integrate positions,
// `relax_iterations` relax sweeps, and after the last substep a restitution sweep when the
// step has restitution.
fn phases_in_substep(s: u32) -> u32 {
    var count = 3u + (params.iterations + params.relax_iterations) * COLOR_SLOT_COUNT;
    if ENABLE_RESTITUTION && params.restitution != 0u && s + 1u == params.substeps {
        count += COLOR_SLOT_COUNT;
    }
    return count;
}

// The graph colors and the overflow set.
override COLOR_SLOT_COUNT: u32 = OVERFLOW_COLOR + 1u;

// Phase q of a substep.
fn phase_at(q: u32) -> Phase {
    if q == 0u {
        return Phase(PHASE_VELOCITIES_AND_WARM, 0u, 0u);
    }
    if q == 1u {
        return Phase(PHASE_COLOR, PASS_WARM_START, OVERFLOW_COLOR);
    }
    let solve_end = 2u + params.iterations * COLOR_SLOT_COUNT;
    if q < solve_end {
        return Phase(PHASE_COLOR, PASS_SOLVE, (q - 2u) % COLOR_SLOT_COUNT);
    }
    if q == solve_end {
        return Phase(PHASE_POSITIONS, 0u, 0u);
    }
    let relax_end = solve_end + 1u + params.relax_iterations * COLOR_SLOT_COUNT;
    if q < relax_end {
        return Phase(PHASE_COLOR, PASS_RELAX, (q - solve_end - 1u) % COLOR_SLOT_COUNT);
    }
    return Phase(PHASE_COLOR, PASS_RESTITUTION, (q - relax_end) % COLOR_SLOT_COUNT);
}

// Items (bodies, or constraints of one color) per thread in one chunk of a phase of `count`
// items: one, or as many as spread the phase over `groups` to `2 * groups` chunks (rounded
// down), so that a large phase takes one or two tickets and counts per workgroup rather than
// one per 32 items (each ticket and count is an atomic on one of two counters that every
// workgroup uses).
fn items_per_thread(count: u32, groups: u32) -> u32 {
    return max(1u, count / (SOLVE_STEP_WORKGROUP_SIZE * groups));
}

// The items of `phase`: bodies, a color's constraints, or the overflow set's.
fn phase_items(phase: Phase) -> u32 {
    if phase.kind != PHASE_COLOR {
        return params.body_count;
    }
    return color_offsets[phase.color + 1u] - color_offsets[phase.color];
}

// Chunks of `phase` with `groups` workgroups: SOLVE_STEP_WORKGROUP_SIZE * items_per_thread
// items each; the overflow set is one chunk (one thread) when it has constraints.
fn phase_chunks(phase: Phase, groups: u32) -> u32 {
    let count = phase_items(phase);
    if phase.kind == PHASE_COLOR && phase.color == OVERFLOW_COLOR {
        return min(count, 1u);
    }
    let size = SOLVE_STEP_WORKGROUP_SIZE * items_per_thread(count, groups);
    return (count + size - 1u) / size;
}

// Chunk `chunk` of `phase` with `groups` workgroups, by every thread of the workgroup.
fn run_chunk(phase: Phase, chunk: u32, groups: u32, local: u32) {
    let count = phase_items(phase);
    if phase.kind == PHASE_COLOR && phase.color == OVERFLOW_COLOR {
        if local == 0u {
            for (var k = color_offsets[OVERFLOW_COLOR]; k < color_offsets[OVERFLOW_COLOR + 1u]; k++) {
                visit_constraint(k, phase.pass_kind);
            }
        }
        return;
    }
    let size = SOLVE_STEP_WORKGROUP_SIZE * items_per_thread(count, groups);
    let end = min((chunk + 1u) * size, count);
    for (var i = chunk * size + local; i < end; i += SOLVE_STEP_WORKGROUP_SIZE) {
        if phase.kind == PHASE_COLOR {
            visit_constraint(color_offsets[phase.color] + i, phase.pass_kind);
        } else if phase.kind == PHASE_VELOCITIES_AND_WARM {
            velocities[i] = integrate_velocity(
                bodies[i],
                poses[i].rotation,
                solver_bodies[i],
                velocities[i],
                params.gravity.xyz,
                params.h,
            );
            warm_start_body(i);
        } else {
            var velocity = velocities[i];
            var state = solver_bodies[i];
            integrate_position(bodies[i], poses[i].rotation, &velocity, &state, params.h);
            velocities[i] = velocity;
            solver_bodies[i] = state;
        }
    }
}

// Whether the chunks of `phase` load their constraints before the wait: a graph color's
// chunks when each thread visits at most one constraint (the overflow set runs in one thread,
// and a thread with several constraints visits them in run_chunk).
fn loads_early(phase: Phase, groups: u32) -> bool {
    return phase.kind == PHASE_COLOR && phase.color != OVERFLOW_COLOR
        && items_per_thread(phase_items(phase), groups) == 1u;
}

// No constraint to load early.
const NO_EARLY_SLOT: u32 = 0xffffffffu;

// The slot thread `local` visits in chunk `chunk` of `phase` when the phase loads early
// (`loads_first`, from loads_early) and the thread has a constraint, else NO_EARLY_SLOT.
fn early_slot(loads_first: bool, phase: Phase, chunk: u32, local: u32) -> u32 {
    if !loads_first {
        return NO_EARLY_SLOT;
    }
    let i = chunk * SOLVE_STEP_WORKGROUP_SIZE + local;
    if i >= phase_items(phase) {
        return NO_EARLY_SLOT;
    }
    return color_offsets[phase.color] + i;
}

// How a workgroup waits for the phases before its chunk and counts its chunk done. On a GPU,
// thread 0 waits (an atomic load) and counts (one add per chunk), and workgroup barriers with
// device-scope acquire-release semantics (storageBarrier) order the other threads' accesses
// against it. On lavapipe those barriers do not order them (the bits then differed from run to
// run with two workgroups), and its compiler may lift an atomic load out of a loop, so there
// every thread counts itself done and waits with a read-modify-write, and the counter counts
// threads. (CPU adapters run one workgroup anyway: solve_step.rs, SOLVE_STEP_CPU_GROUPS.)
override SOLVE_STEP_PER_THREAD_SYNC: bool;

// Threads counted per chunk done.
fn done_per_chunk() -> u32 {
    if SOLVE_STEP_PER_THREAD_SYNC {
        return SOLVE_STEP_WORKGROUP_SIZE;
    }
    return 1u;
}

// Polls after which a wait gives up (a guard against a bug hanging the GPU): it then sets
// step_progress[2], which the host reads with the step's stats and reports as an error.
override SOLVE_STEP_WAIT_LIMIT: u32;

// Waits until `chunks` chunks are done. Once a wait has given up, the step's results are
// wrong anyway and no later wait polls at all (else every wait of every workgroup would poll
// to the limit again, and the guard would not bound the hang).
fn wait_for(chunks: u32, local: u32) {
    let needed = chunks * done_per_chunk();
    if SOLVE_STEP_PER_THREAD_SYNC || local == 0u {
        var polls = 0u;
        loop {
            var seen: u32;
            if SOLVE_STEP_PER_THREAD_SYNC {
                seen = atomicOr(&step_progress[1], 0u);
            } else {
                seen = atomicLoad(&step_progress[1]);
            }
            if seen >= needed {
                break;
            }
            polls++;
            if polls >= SOLVE_STEP_WAIT_LIMIT {
                atomicStore(&step_progress[2], 1u);
                break;
            }
            // Every 1,024 polls: has another wait given up?
            if (polls & 1023u) == 0u && atomicOr(&step_progress[2], 0u) != 0u {
                break;
            }
        }
    }
    storageBarrier();
}

// Counts the workgroup's chunk done, after its writes.
fn count_done(local: u32) {
    storageBarrier();
    if SOLVE_STEP_PER_THREAD_SYNC || local == 0u {
        atomicAdd(&step_progress[1], 1u);
    }
}

// The ticket thread 0 took, for the whole workgroup.
var<workgroup> claimed: u32;

@compute @workgroup_size(SOLVE_STEP_WORKGROUP_SIZE)
fn main(
    @builtin(local_invocation_index) local: u32,
    @builtin(num_workgroups) grid: vec3<u32>,
) {
    let groups = grid.x;
    // The phase holding the last ticket taken: substep, phase within it, its first ticket and
    // its chunks. Tickets only grow, so each workgroup walks the phases once.
    var substep = 0u;
    var q = 0u;
    var phase = phase_at(0u);
    var first_ticket = 0u;
    var chunks = phase_chunks(phase, groups);
    loop {
        if local == 0u {
            claimed = atomicAdd(&step_progress[0], 1u);
        }
        let ticket = workgroupUniformLoad(&claimed);
        while substep < params.substeps && ticket >= first_ticket + chunks {
            first_ticket += chunks;
            q += 1u;
            if q == phases_in_substep(substep) {
                q = 0u;
                substep += 1u;
            }
            phase = phase_at(q);
            chunks = phase_chunks(phase, groups);
        }
        if substep >= params.substeps {
            // Every chunk of the step was handed out.
            break;
        }
        // A color chunk of one constraint per thread loads its constraint before the wait:
        // everything but the impulses is fixed from prepare to store, so the load is not on
        // the path from the phases before to this one, and after the wait the impulses and
        // the bodies (whose indices the constraint gave) are read at once.
        let loads_first = loads_early(phase, groups);
        let early = early_slot(loads_first, phase, ticket - first_ticket, local);
        var constraint: GpuConstraint;
        if early != NO_EARLY_SLOT {
            constraint = load_constraint(early);
        }
        // Every ticket before first_ticket belongs to an earlier phase: once that many chunks
        // are done, so are those phases (no chunk of this phase or a later one can finish
        // before them).
        wait_for(first_ticket, local);
        if early != NO_EARLY_SLOT {
            reload_pass_impulses(early, &constraint);
            visit_loaded(early, phase.pass_kind, &constraint);
        } else if !loads_first {
            run_chunk(phase, ticket - first_ticket, groups, local);
        }
        count_done(local);
    }
}
