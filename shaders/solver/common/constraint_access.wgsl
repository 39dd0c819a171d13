// requires: solver/common/contact_math.wgsl solver/common/constraint_write.wgsl
// One constraint pass on the constraint in one slot: load it and its two bodies, apply the
// pass, store its impulses and the dynamic bodies' velocities (fixed and kinematic bodies are shared by
// many constraints of a color and are never written). Used by solve_color and solve_fused.
//
// Expects the including kernel to declare: params: SolverParams (uniform),
// solver_bodies: array<GpuSolverBody>, velocities: array<GpuVelocity> (read_write),
// constraints: array<vec4<f32>> (read_write, constraint_store.wgsl's rows).

fn visit_constraint(s: u32, kind: u32) {
    var c = load_constraint(s);
    visit_loaded(s, kind, &c);
}

// The pass on the constraint of slot s, already loaded into c (whose impulses are current).
fn visit_loaded(s: u32, kind: u32, constraint: ptr<function, GpuConstraint>) {
    var c = *constraint;
    var a = body_sim(velocities[body_slot(c.body_a)], solver_bodies[body_slot(c.body_a)]);
    var b = body_sim(velocities[body_slot(c.body_b)], solver_bodies[body_slot(c.body_b)]);
    if kind == PASS_WARM_START {
        warm_start_points(&c, &a, &b);
    } else if kind == PASS_SOLVE {
        let friction = params.relax_only_friction == 0u;
        solve_points(&c, &a, &b, true, params.inv_h, params.max_push_out, friction);
    } else if kind == PASS_RELAX {
        solve_points(&c, &a, &b, false, params.inv_h, params.max_push_out, true);
    } else {
        restitution_points(&c, &a, &b, params.restitution_threshold);
    }
    store_pass_impulses(s, c);
    if (c.flags & CONSTRAINT_DYNAMIC_A) != 0u {
        velocities[body_slot(c.body_a)] = sim_velocity(a);
    }
    if (c.flags & CONSTRAINT_DYNAMIC_B) != 0u {
        velocities[body_slot(c.body_b)] = sim_velocity(b);
    }
}
