// requires: solver/common/contact_math.wgsl solver/common/constraint_write.wgsl
// Building one constraint from its manifold: normal and two friction rows per point,
// effective masses, anchors, softness, and the carried warm-start impulses. Used by
// prepare_contacts (one thread per manifold) and solve_fused (a workgroup loop).
//
// Expects the including kernel to declare: params: SolverParams (uniform),
// manifolds: array<GpuManifold>, contacts: array<GpuContact>, bodies: array<GpuBody>,
// poses: array<GpuPose>, velocities: array<GpuVelocity>, solver_bodies: array<GpuSolverBody>,
// previous_tilts: array<GpuTilt>, constraints: array<vec4<f32>> (read_write, constraint_store.wgsl).

// Builds the constraint of manifold i and stores it in slot s (its position in the order by
// color).
fn prepare_constraint(i: u32, s: u32) {
    let manifold = manifolds[i];
    let a = manifold.body_a;
    let b = manifold.body_b;
    let sim_a = body_sim(velocities[body_slot(a)], solver_bodies[body_slot(a)]);
    let sim_b = body_sim(velocities[body_slot(b)], solver_bodies[body_slot(b)]);
    let tilt = carried_tilt(manifold, previous_tilts[min(manifold.previous, arrayLength(&previous_tilts) - 1u)], poses[a].rotation);
    var c = begin_constraint(manifold, bodies[a], bodies[b], tilt, params);
    for (var p = 0u; p < MAX_MANIFOLD_POINTS; p++) {
        if p >= c.point_count {
            break;
        }
        let point = contacts[i * MAX_MANIFOLD_POINTS + p];
        c.points[p] = prepare_point(c, point, poses[a].position.xyz, poses[b].position.xyz, sim_a, sim_b, params.warm_start_scale);
    }
    finish_constraint(&c, sim_a, sim_b);
    store_constraint(s, c);
}
