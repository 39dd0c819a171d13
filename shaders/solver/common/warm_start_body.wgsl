// requires: solver/common/constraint_access.wgsl
// The warm start of the graph colors for one body (warm_start_bodies, solve_step). A warm
// start applies each constraint's stored impulses to its two bodies, and what it adds to a
// body's velocity depends on that body's velocity only (through the `turns` test) and on the
// constraint, never on the other body. A body has at most one constraint per color, so in the
// colored sweep its velocity takes its constraints' terms one at a time in color order. Here
// the body walks the same constraints in the same order (prepare_contacts lists them per body
// and color in the coloring's marks) and applies only its own side, through the same functions
// (warm_start_points, against a body that takes nothing), so every velocity gets the same
// operations in the same order as in the colored sweep. Each constraint's running totals
// (total_normal_impulse) are stored by body A's walk when A is dynamic, else by B's.
//
// Expects the including kernel to declare, besides what constraint_access.wgsl expects:
// color_marks: array<u32> (per (body, graph color) the slot + 1 of the body's constraint of
// that color, or 0).

// A body that takes no impulse: no mass, no turning; its side of the arithmetic is dropped.
fn immovable_body() -> BodySim {
    return BodySim(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec4<f32>(0.0, 0.0, 0.0, 1.0),
        vec3<f32>(0.0), mat3x3<f32>(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0)), false);
}

// The warm start of body `body`'s constraints of the graph colors (the overflow set is not
// listed per body: it follows in one thread, as in the colored sweep).
fn warm_start_body(body: u32) {
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
