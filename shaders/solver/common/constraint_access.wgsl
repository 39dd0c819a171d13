// requires: solver/common/contact_math.wgsl
// One constraint pass on one constraint: load it and its two bodies, apply the pass, store
// the constraint and the dynamic bodies' velocities (fixed and kinematic bodies are shared by
// many constraints of a color and are never written). Used by solve_color and solve_fused.
//
// Expects the including kernel to declare: params: SolverParams (uniform),
// solver_bodies: array<GpuSolverBody>, velocities: array<GpuVelocity> (read_write),
// constraints: array<GpuConstraint> (read_write).

// Writes back what a pass changes in constraint `i`, from its local copy `c`: the points'
// accumulated impulses and the tilt impulses. The rest of the 368 bytes (anchors, masses,
// normal, tangents) is fixed from prepare to store, so writing it again would only cost
// bandwidth.
fn store_pass_impulses(i: u32, c: GpuConstraint) {
    for (var p = 0u; p < c.point_count; p++) {
        constraints[i].points[p].normal_impulse = c.points[p].normal_impulse;
        constraints[i].points[p].total_normal_impulse = c.points[p].total_normal_impulse;
        constraints[i].points[p].tangent_impulse_1 = c.points[p].tangent_impulse_1;
        constraints[i].points[p].tangent_impulse_2 = c.points[p].tangent_impulse_2;
    }
    constraints[i].tilt_impulse_1 = c.tilt_impulse_1;
    constraints[i].tilt_impulse_2 = c.tilt_impulse_2;
}

fn visit_constraint(i: u32, kind: u32) {
    var c = constraints[i];
    var a = body_sim(velocities[c.body_a], solver_bodies[c.body_a]);
    var b = body_sim(velocities[c.body_b], solver_bodies[c.body_b]);
    if kind == PASS_WARM_START {
        warm_start_points(&c, &a, &b);
    } else if kind == PASS_SOLVE {
        solve_points(&c, &a, &b, true, params.inv_h, params.max_push_out);
    } else if kind == PASS_RELAX {
        solve_points(&c, &a, &b, false, params.inv_h, params.max_push_out);
    } else {
        restitution_points(&c, &a, &b, params.restitution_threshold);
    }
    store_pass_impulses(i, c);
    if (c.flags & CONSTRAINT_DYNAMIC_A) != 0u {
        velocities[c.body_a] = sim_velocity(a);
    }
    if (c.flags & CONSTRAINT_DYNAMIC_B) != 0u {
        velocities[c.body_b] = sim_velocity(b);
    }
}
