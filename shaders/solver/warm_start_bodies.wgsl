// requires: common/indexing.wgsl solver/common/constraint_access.wgsl solver/common/body_slot.wgsl
// warm_start_bodies: the warm-start pass of a substep in one dispatch, one thread per body,
// for the graph colors (the overflow set follows in solve_color's single thread, as in the
// colored sweep). A warm start applies each constraint's stored impulses to its two bodies,
// and what it adds to a body's velocity depends on that body's velocity only (through the
// `turns` test) and on the constraint, never on the other body. A body has at most one
// constraint per color, so in the colored sweep its velocity takes its constraints' terms
// one at a time in color order. Here the body's thread walks the same constraints in the same
// order (prepare_contacts lists them per body and color) and applies only its own side, through
// the same functions (warm_start_points, against a body that takes nothing), so every velocity
// gets the same operations in the same order: the same bits, with 1 dispatch instead of one
// per color. Each constraint's running totals (total_normal_impulse) are stored by the thread
// of body A when A is dynamic, else by B's.
@group(0) @binding(0) var<uniform> params: SolverParams;
@group(0) @binding(1) var<storage, read> solver_bodies: array<GpuSolverBody>;
// `array<GpuVelocity>`, updated.
@group(0) @binding(2) var<storage, read_write> velocities: array<GpuVelocity>;
// The constraint store (`GpuConstraint` rows, by slot); the totals updated.
@group(0) @binding(3) var<storage, read_write> constraints: array<vec4<f32>>;
// The coloring's marks: per (body, graph color) the slot + 1 of the body's constraint of that
// color, or 0 (prepare_contacts.wgsl).
@group(0) @binding(4) var<storage, read> color_marks: array<u32>;

// A body that takes no impulse: no mass, no turning; its side of the arithmetic is dropped.
fn immovable_body() -> BodySim {
    return BodySim(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec4<f32>(0.0, 0.0, 0.0, 1.0),
        vec3<f32>(0.0), mat3x3<f32>(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0)), false);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let body = thread_index(thread);
    if body >= params.body_count {
        return;
    }
    let base = params.body_count + body * GRAPH_COLOR_COUNT;
    let state = solver_bodies[body];
    var velocity = velocities[body];
    var touched = false;
    for (var color = 0u; color < GRAPH_COLOR_COUNT; color++) {
        let entry = color_marks[base + color];
        if entry == 0u {
            continue;
        }
        let s = entry - 1u;
        var c = load_constraint(s);
        var me = body_sim(velocity, state);
        var other = immovable_body();
        if c.body_a == body {
            warm_start_points(&c, &me, &other);
            store_pass_impulses(s, c);
        } else {
            warm_start_points(&c, &other, &me);
            if (c.flags & CONSTRAINT_DYNAMIC_A) == 0u {
                store_pass_impulses(s, c);
            }
        }
        velocity = sim_velocity(me);
        touched = true;
    }
    if touched {
        velocities[body] = velocity;
    }
}
