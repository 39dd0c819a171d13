// requires: common/indexing.wgsl solver/common/constraint_access.wgsl
// requires: solver/common/color_workgroup.wgsl solver/common/prepare_constraint.wgsl
// requires: solver/common/store_slot.wgsl
// The fused path's whole color-and-solve stage, run by ONE workgroup: shared by solve_fused
// (bodies in storage), solve_fused_shared (bodies in workgroup memory) and solve_worlds (one
// workgroup per group of worlds of a batch, bodies in storage), which declare the
// bindings and three hooks: load_velocities(local, n) before prepare, store_bodies(local, n)
// at the end, and sync_bodies(), the barrier that makes one thread's body writes visible to
// the others between colors and body loops. Constraint slots need no barrier between the
// passes: colored_pass gives a slot to the same thread in every pass (and the overflow set to
// thread 0); prepare and finish, which give slots to other threads, use sync_workgroup().
//
// Per-dispatch overhead, not arithmetic, made the thesis's GPU solver slow: a step of the wide
// path issues about 80 dispatches per substep (one per color and pass), while here the colors
// are visited in a loop separated by barriers. The per-constraint and per-body functions are
// the wide path's own (coloring.wgsl, body_math.wgsl, contact_math.wgsl,
// constraint_access.wgsl, prepare_constraint.wgsl), in the same order, so both paths compute
// the same result.

// Constraints per color (overflow last).
var<workgroup> color_counts: array<atomic<u32>, GRAPH_COLOR_COUNT + 1u>;

// Counts the constraints of each color among the n from `base` on and writes color_offsets
// (from `base` on); returns (to every thread) one past the highest color in use, overflow
// excluded.
fn count_colors_in_workgroup(local: u32, base: u32, n: u32) -> u32 {
    for (var c = local; c <= GRAPH_COLOR_COUNT; c += WORKGROUP_SIZE) {
        atomicStore(&color_counts[c], 0u);
    }
    workgroupBarrier();
    for (var k = local; k < n; k += WORKGROUP_SIZE) {
        let color = color_state[base + k].color;
        if color <= OVERFLOW_COLOR {
            atomicAdd(&color_counts[color], 1u);
        }
    }
    workgroupBarrier();
    var used = 0u;
    if local == 0u {
        var offset = base;
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

// Thread c lays out the constraints of color c (of the n from `base` on) in ascending index
// order: the same stable order the wide path's radix sort produces.
fn order_by_color(local: u32, base: u32, n: u32) {
    // Empty manifolds too (EMPTY_COLOR, after the overflow set): every slot gets a manifold.
    if local <= EMPTY_COLOR {
        var slot = color_offsets[local];
        for (var i = base; i < base + n; i++) {
            if color_state[i].color == local {
                color_order[slot] = i;
                slot++;
            }
        }
    }
    sync_workgroup();
}

// One pass over every constraint, color after color, then the overflow set in one thread.
fn colored_pass(local: u32, used_colors: u32, kind: u32) {
    for (var color = 0u; color < used_colors; color++) {
        let end = color_offsets[color + 1u];
        for (var k = color_offsets[color] + local; k < end; k += WORKGROUP_SIZE) {
            visit_constraint(k, kind);
        }
        sync_bodies();
    }
    if local == 0u {
        let end = color_offsets[OVERFLOW_COLOR + 1u];
        for (var k = color_offsets[OVERFLOW_COLOR]; k < end; k++) {
            visit_constraint(k, kind);
        }
    }
    sync_bodies();
}

// The whole stage, run by every thread of the workgroup.
fn fused_solve(local: u32) {
    fused_solve_range(local, 0u, contact_work.count, 0u, params.body_count);
}

// The whole stage for the n constraints from `base` on and the body_count bodies from
// first_body on, which no other constraint touches: one world (solve_fused: all of them;
// solve_worlds: one world per workgroup).
fn fused_solve_range(local: u32, base: u32, n: u32, first_body: u32, body_count: u32) {
    // color: every round here (color_marks was cleared before the dispatch).
    list_all_in_workgroup(local, base, n);
    color_rounds_in_workgroup(local, base, n, 0u);
    let used_colors = count_colors_in_workgroup(local, base, n);
    order_by_color(local, base, n);

    // prepare
    load_velocities(local, body_count);
    for (var k = local; k < body_count; k += WORKGROUP_SIZE) {
        let b = first_body + k;
        solver_bodies[body_slot(b)] = prepare_body(bodies[b], poses[b]);
    }
    sync_workgroup();
    for (var s = base + local; s < base + n; s += WORKGROUP_SIZE) {
        prepare_constraint(color_order[s], s);
    }
    sync_workgroup();

    // substeps
    for (var substep = 0u; substep < params.substeps; substep++) {
        for (var k = local; k < body_count; k += WORKGROUP_SIZE) {
            let b = first_body + k;
            velocities[body_slot(b)] = integrate_velocity(
                bodies[b],
                poses[b].rotation,
                solver_bodies[body_slot(b)],
                velocities[body_slot(b)],
                params.gravity.xyz,
                params.h,
            );
        }
        sync_bodies();
        colored_pass(local, used_colors, PASS_WARM_START);
        for (var k = 0u; k < params.iterations; k++) {
            colored_pass(local, used_colors, PASS_SOLVE);
        }
        for (var k = local; k < body_count; k += WORKGROUP_SIZE) {
            let b = first_body + k;
            var velocity = velocities[body_slot(b)];
            var state = solver_bodies[body_slot(b)];
            integrate_position(bodies[b], poses[b].rotation, &velocity, &state, params.h);
            velocities[body_slot(b)] = velocity;
            solver_bodies[body_slot(b)] = state;
        }
        sync_bodies();
        for (var k = 0u; k < params.relax_iterations; k++) {
            colored_pass(local, used_colors, PASS_RELAX);
        }
    }
    if ENABLE_RESTITUTION && params.restitution != 0u {
        colored_pass(local, used_colors, PASS_RESTITUTION);
    }

    // finish: slots were last written by their pass's thread, and are stored by another.
    sync_workgroup();
    for (var s = base + local; s < base + n; s += WORKGROUP_SIZE) {
        store_slot(s);
    }
    // The tilts read the poses the manifolds were made from: finalize only after them.
    sync_workgroup();
    for (var k = local; k < body_count; k += WORKGROUP_SIZE) {
        let b = first_body + k;
        poses[b] = finalize_pose(bodies[b].kind, poses[b], solver_bodies[body_slot(b)]);
    }
    store_bodies(local, body_count);
}
