// requires: solver/common/body_math.wgsl
// The per-constraint math of the solve stage as functions on function-local copies, mirroring
// crates/tumble-solver (constraint.rs, contact_solver.rs, tangent_basis.rs) step for step, so
// the GPU and the CPU solver pass the same stability suite.

const PI: f32 = 3.14159265358979;

// A body as the constraint passes see it.
struct BodySim {
    linear_velocity: vec3<f32>,
    angular_velocity: vec3<f32>,
    delta_position: vec3<f32>,
    delta_rotation: vec4<f32>,
    inverse_mass: vec3<f32>,
    inverse_inertia: mat3x3<f32>,
    // Whether the body has an angular state the passes must use (see `body_turns`).
    turns: bool,
}

// Whether a body's angular terms enter its constraints: it has a nonzero world inverse
// inertia, angular velocity or delta rotation. A fixed body, a body with every rotation
// locked, and every body when rotation is compiled out (body_math.wgsl zeroes their inverse
// inertia and angular velocity) have none, and the passes skip their angular terms.
//
// This is decided per body at run time, in both pipeline variants, and not by the
// ENABLE_ROTATION switch: the contact rows must run the very same code whether rotation is
// compiled in or out, or a scene without rotation does not step to the same bits both ways.
// Shader compilers may contract and reorder floating-point arithmetic, and do it differently
// in two different programs: on an H100 through Vulkan, with the angular terms removed at
// compile time, a pile of rotation-locked cubes lost bitwise equality with the rotation-on
// pipelines at its first contacts (linear velocities differing in the last bits), even with
// every angular term skipped at run time in the latter; with the same run-time skip in both
// it stays equal (benches/src/bin/effects_table.rs --diff rotation). The branch is uniform
// per constraint and also saves the angular work of fixed and locked bodies in every scene.
fn body_turns(velocity: GpuVelocity, state: GpuSolverBody) -> bool {
    let zero = vec3<f32>(0.0);
    let inertia = any(state.inverse_inertia_x.xyz != zero) || any(state.inverse_inertia_y.xyz != zero)
        || any(state.inverse_inertia_z.xyz != zero);
    return inertia || any(velocity.angular.xyz != zero) || any(state.delta_rotation.xyz != zero);
}

fn body_sim(velocity: GpuVelocity, state: GpuSolverBody) -> BodySim {
    return BodySim(
        velocity.linear.xyz,
        velocity.angular.xyz,
        state.delta_position.xyz,
        state.delta_rotation,
        state.inverse_mass.xyz,
        mat3x3<f32>(state.inverse_inertia_x.xyz, state.inverse_inertia_y.xyz, state.inverse_inertia_z.xyz),
        body_turns(velocity, state),
    );
}

// The velocity of a body as stored between passes.
fn sim_velocity(b: BodySim) -> GpuVelocity {
    return GpuVelocity(vec4<f32>(b.linear_velocity, 0.0), vec4<f32>(b.angular_velocity, 0.0));
}

struct TangentBasis {
    t1: vec3<f32>,
    t2: vec3<f32>,
}

// An orthonormal pair (t1, t2) with t1 x t2 = n (Duff et al., JCGT 2017), as on the CPU.
fn tangent_basis(n: vec3<f32>) -> TangentBasis {
    // copysign(1, n.z): the sign bit decides, so -0.0 gives -1 exactly as on the CPU.
    let sign = select(1.0, -1.0, (bitcast<u32>(n.z) & 0x80000000u) != 0u);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return TangentBasis(
        vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vec3<f32>(b, sign + n.y * n.y * a, -n.y),
    );
}

// (r x d) . I^-1 (r x d): the angular part of a row's inverse effective mass.
fn angular_term(inverse_inertia: mat3x3<f32>, r: vec3<f32>, d: vec3<f32>) -> f32 {
    let rd = cross(r, d);
    return dot(rd, inverse_inertia * rd);
}

// 1 / (J M^-1 J^T) of the row along d, or 0 when neither body can move along it.
fn row_mass(a: BodySim, b: BodySim, anchor_a: vec3<f32>, anchor_b: vec3<f32>, d: vec3<f32>) -> f32 {
    let d2 = d * d;
    let k = dot(a.inverse_mass, d2) + dot(b.inverse_mass, d2)
        + angular_term(a.inverse_inertia, anchor_a, d)
        + angular_term(b.inverse_inertia, anchor_b, d);
    return select(0.0, 1.0 / k, k > 0.0);
}

// Velocity of B's anchor relative to A's anchor (linear only when neither body turns).
fn relative_velocity(a: BodySim, b: BodySim, anchor_a: vec3<f32>, anchor_b: vec3<f32>) -> vec3<f32> {
    if a.turns || b.turns {
        return b.linear_velocity + cross(b.angular_velocity, anchor_b) - a.linear_velocity
            - cross(a.angular_velocity, anchor_a);
    }
    return b.linear_velocity - a.linear_velocity;
}

// Applies impulse p at the anchors: -p on A, +p on B (angular parts on bodies that turn).
fn apply_impulse(a: ptr<function, BodySim>, b: ptr<function, BodySim>, anchor_a: vec3<f32>, anchor_b: vec3<f32>, p: vec3<f32>) {
    (*a).linear_velocity -= (*a).inverse_mass * p;
    (*b).linear_velocity += (*b).inverse_mass * p;
    if (*a).turns {
        (*a).angular_velocity -= (*a).inverse_inertia * cross(anchor_a, p);
    }
    if (*b).turns {
        (*b).angular_velocity += (*b).inverse_inertia * cross(anchor_b, p);
    }
}

// The header of a manifold's constraint (prepare_contact): bodies, normal and tangents,
// combined friction and restitution, softness. Its points come from prepare_point.
// `tilt` is the pair's tilt impulse carried from the last step (world vector).
fn begin_constraint(manifold: GpuManifold, body_a: GpuBody, body_b: GpuBody, tilt: vec3<f32>, params: SolverParams) -> GpuConstraint {
    let dynamic_a = body_a.kind == BODY_DYNAMIC;
    let dynamic_b = body_b.kind == BODY_DYNAMIC;
    let normal = manifold.normal.xyz;
    let basis = tangent_basis(normal);
    // Contacts with an immovable body are stiffer (the host makes both equal for Baumgarte).
    var softness = params.static_softness;
    if dynamic_a && dynamic_b {
        softness = params.contact_softness;
    }
    var c: GpuConstraint;
    c.body_a = manifold.body_a;
    c.body_b = manifold.body_b;
    c.point_count = min(manifold.len, MAX_MANIFOLD_POINTS);
    c.flags = select(0u, CONSTRAINT_DYNAMIC_A, dynamic_a) | select(0u, CONSTRAINT_DYNAMIC_B, dynamic_b);
    // Friction: sqrt(mu_a mu_b); restitution: the larger (tumble-solver's material.rs).
    c.normal = vec4<f32>(normal, sqrt(body_a.friction * body_b.friction));
    c.tangent1 = vec4<f32>(basis.t1, max(body_a.restitution, body_b.restitution));
    c.tangent2 = vec4<f32>(basis.t2, params.slop);
    c.softness = vec4<f32>(softness.xyz, 0.0);
    c.tilt_impulse_1 = params.warm_start_scale * dot(tilt, basis.t1);
    c.tilt_impulse_2 = params.warm_start_scale * dot(tilt, basis.t2);
    return c;
}

// The carried tilt impulse of a manifold: last step's, when the pair had a manifold then and
// its normal turned by less than the angle of PERSIST_NORMAL_COS in body A's frame (the same
// patch), else zero (also for a manifold without points, which is no contact).
fn carried_tilt(manifold: GpuManifold, previous: GpuTilt, rotation_a: vec4<f32>) -> vec3<f32> {
    if manifold.len == 0u || manifold.previous == NO_PREVIOUS {
        return vec3<f32>(0.0);
    }
    let local = quat_rotate(quat_conjugate(rotation_a), manifold.normal.xyz);
    if dot(local, previous.local_normal.xyz) >= PERSIST_NORMAL_COS {
        return previous.impulse.xyz;
    }
    return vec3<f32>(0.0);
}

// Completes a constraint whose points are prepared: the patch's inscribed radius (from the
// points' in-plane distances to their centroid, times cos(pi / n): exact for a regular
// polygon; 0 below three points) and the tilt rows' effective masses.
fn finish_constraint(c: ptr<function, GpuConstraint>, a: BodySim, b: BodySim) {
    let n = (*c).point_count;
    let normal = (*c).normal.xyz;
    if n >= 3u {
        var centroid = vec3<f32>(0.0);
        for (var i = 0u; i < MAX_MANIFOLD_POINTS; i++) {
            if i >= n {
                break;
            }
            centroid += (*c).points[i].anchor_a.xyz;
        }
        centroid = centroid / f32(n);
        var nearest = 3.0e38;
        for (var i = 0u; i < MAX_MANIFOLD_POINTS; i++) {
            if i >= n {
                break;
            }
            let d = (*c).points[i].anchor_a.xyz - centroid;
            nearest = min(nearest, length(d - normal * dot(d, normal)));
        }
        (*c).patch_radius = nearest * cos(PI / f32(n));
    }
    // Tilt rows exist only for a patch with a nonzero radius: an impulse carried from an
    // earlier patch onto an edge or a point would act unclamped every substep (as on the CPU).
    if (*c).patch_radius <= 0.0 {
        (*c).tilt_impulse_1 = 0.0;
        (*c).tilt_impulse_2 = 0.0;
    }
    let angular = a.inverse_inertia + b.inverse_inertia;
    let k1 = dot((*c).tangent1.xyz, angular * (*c).tangent1.xyz);
    let k2 = dot((*c).tangent2.xyz, angular * (*c).tangent2.xyz);
    (*c).tilt_mass_1 = select(0.0, 1.0 / k1, k1 > 0.0);
    (*c).tilt_mass_2 = select(0.0, 1.0 / k2, k2 > 0.0);
}

// Applies angular impulse `torque`: -torque on A, +torque on B (on bodies that turn).
fn apply_torque(a: ptr<function, BodySim>, b: ptr<function, BodySim>, torque: vec3<f32>) {
    if (*a).turns {
        (*a).angular_velocity -= (*a).inverse_inertia * torque;
    }
    if (*b).turns {
        (*b).angular_velocity += (*b).inverse_inertia * torque;
    }
}

// The tilt rows of a face patch: no relative rotation about the two tangents, within the
// torque n * r * min(lambda_i) the patch can add before its least loaded point lets go
// (solve_tilt on the CPU).
fn solve_tilt(c: ptr<function, GpuConstraint>, a: ptr<function, BodySim>, b: ptr<function, BodySim>) {
    let n = (*c).point_count;
    var least = 3.0e38;
    for (var i = 0u; i < MAX_MANIFOLD_POINTS; i++) {
        if i >= n {
            break;
        }
        least = min(least, (*c).points[i].normal_impulse);
    }
    let limit = f32(n) * (*c).patch_radius * max(least, 0.0);
    let t1 = (*c).tangent1.xyz;
    let t2 = (*c).tangent2.xyz;
    let relative = (*b).angular_velocity - (*a).angular_velocity;
    let old = vec2<f32>((*c).tilt_impulse_1, (*c).tilt_impulse_2);
    var updated = vec2<f32>(old.x - (*c).tilt_mass_1 * dot(relative, t1), old.y - (*c).tilt_mass_2 * dot(relative, t2));
    let length = sqrt(updated.x * updated.x + updated.y * updated.y);
    if length > limit {
        let scale = select(0.0, limit / length, length > 0.0);
        updated = vec2<f32>(updated.x * scale, updated.y * scale);
    }
    (*c).tilt_impulse_1 = updated.x;
    (*c).tilt_impulse_2 = updated.y;
    apply_torque(a, b, t1 * (updated.x - old.x) + t2 * (updated.y - old.y));
}

// One point of a constraint: anchors from the bodies' centres at the start of the step, base
// separation, effective masses, warm-start impulses projected on this step's tangents, and
// the approach speed for restitution.
fn prepare_point(
    c: GpuConstraint,
    point: GpuContact,
    centre_a: vec3<f32>,
    centre_b: vec3<f32>,
    a: BodySim,
    b: BodySim,
    warm_start_scale: f32,
) -> GpuConstraintPoint {
    let normal = c.normal.xyz;
    let t1 = c.tangent1.xyz;
    let t2 = c.tangent2.xyz;
    let anchor_a = point.position.xyz - centre_a;
    let anchor_b = point.position.xyz - centre_b;
    let dv = relative_velocity(a, b, anchor_a, anchor_b);
    var cp: GpuConstraintPoint;
    cp.anchor_a = vec4<f32>(anchor_a, -point.depth - dot(anchor_b - anchor_a, normal));
    cp.anchor_b = vec4<f32>(anchor_b, row_mass(a, b, anchor_a, anchor_b, normal));
    cp.tangent_mass_1 = row_mass(a, b, anchor_a, anchor_b, t1);
    cp.tangent_mass_2 = row_mass(a, b, anchor_a, anchor_b, t2);
    cp.normal_impulse = warm_start_scale * point.normal_impulse;
    cp.total_normal_impulse = 0.0;
    cp.tangent_impulse_1 = warm_start_scale * dot(point.friction_impulse.xyz, t1);
    cp.tangent_impulse_2 = warm_start_scale * dot(point.friction_impulse.xyz, t2);
    cp.relative_velocity = dot(dv, normal);
    return cp;
}

// Re-applies the accumulated impulses at the start of a substep.
fn warm_start_points(c: ptr<function, GpuConstraint>, a: ptr<function, BodySim>, b: ptr<function, BodySim>) {
    let normal = (*c).normal.xyz;
    let t1 = (*c).tangent1.xyz;
    let t2 = (*c).tangent2.xyz;
    for (var i = 0u; i < MAX_MANIFOLD_POINTS; i++) {
        if i >= (*c).point_count {
            break;
        }
        let cp = (*c).points[i];
        let p = normal * cp.normal_impulse + t1 * cp.tangent_impulse_1 + t2 * cp.tangent_impulse_2;
        (*c).points[i].total_normal_impulse += cp.normal_impulse;
        apply_impulse(a, b, cp.anchor_a.xyz, cp.anchor_b.xyz, p);
    }
    apply_torque(a, b, t1 * (*c).tilt_impulse_1 + t2 * (*c).tilt_impulse_2);
}

// Non-penetration rows of every point: speculative, soft-biased or relaxed
// (solve_normal_rows on the CPU).
fn solve_normal_points(
    c: ptr<function, GpuConstraint>,
    a: ptr<function, BodySim>,
    b: ptr<function, BodySim>,
    use_bias: bool,
    inv_h: f32,
    max_push_out: f32,
) {
    let normal = (*c).normal.xyz;
    let dp = (*b).delta_position - (*a).delta_position;
    let count = (*c).point_count;
    let turns = (*a).turns || (*b).turns;
    for (var i = 0u; i < MAX_MANIFOLD_POINTS; i++) {
        if i >= count {
            break;
        }
        let cp = (*c).points[i];
        let anchor_a = cp.anchor_a.xyz;
        let anchor_b = cp.anchor_b.xyz;
        // The separation's change: the linear sum is computed on its own, as the pipelines
        // without rotation compute it, and replaced when a body turns (the anchors turned by
        // the bodies' delta rotations), so that its operations are the same in both.
        var ds = dp + anchor_b - anchor_a;
        if turns {
            ds = dp + quat_rotate((*b).delta_rotation, anchor_b)
                - quat_rotate((*a).delta_rotation, anchor_a);
        }
        let s = cp.anchor_a.w + dot(ds, normal);
        var bias = 0.0;
        var mass_scale = 1.0;
        var impulse_scale = 0.0;
        if s > 0.0 {
            // Speculative: approach by at most the gap this substep.
            bias = s * inv_h;
        } else if use_bias {
            let soft = (*c).softness;
            bias = max(soft.y * soft.x * min(s + (*c).tangent2.w, 0.0), -max_push_out);
            mass_scale = soft.y;
            impulse_scale = soft.z;
        }
        let vn = dot(relative_velocity(*a, *b, anchor_a, anchor_b), normal);
        let delta = -cp.anchor_b.w * (mass_scale * vn + bias) - impulse_scale * cp.normal_impulse;
        let accumulated = max(cp.normal_impulse + delta, 0.0);
        let applied = accumulated - cp.normal_impulse;
        (*c).points[i].normal_impulse = accumulated;
        (*c).points[i].total_normal_impulse += applied;
        apply_impulse(a, b, anchor_a, anchor_b, normal * applied);
    }
}

// Coulomb friction clamped to the disc of radius mu * normal impulse; true when every point
// was clamped, the whole patch sliding (solve_friction_rows on the CPU).
fn solve_friction_points(c: ptr<function, GpuConstraint>, a: ptr<function, BodySim>, b: ptr<function, BodySim>) -> bool {
    let friction = (*c).normal.w;
    let t1 = (*c).tangent1.xyz;
    let t2 = (*c).tangent2.xyz;
    var all_slide = true;
    for (var i = 0u; i < MAX_MANIFOLD_POINTS; i++) {
        if i >= (*c).point_count {
            break;
        }
        let cp = (*c).points[i];
        let dv = relative_velocity(*a, *b, cp.anchor_a.xyz, cp.anchor_b.xyz);
        let old = vec2<f32>(cp.tangent_impulse_1, cp.tangent_impulse_2);
        var updated = vec2<f32>(old.x - cp.tangent_mass_1 * dot(dv, t1), old.y - cp.tangent_mass_2 * dot(dv, t2));
        let limit = friction * cp.normal_impulse;
        let length = sqrt(updated.x * updated.x + updated.y * updated.y);
        if length > limit {
            let scale = select(0.0, limit / length, length > 0.0);
            updated = vec2<f32>(updated.x * scale, updated.y * scale);
        } else {
            all_slide = false;
        }
        (*c).points[i].tangent_impulse_1 = updated.x;
        (*c).points[i].tangent_impulse_2 = updated.y;
        let p = t1 * (updated.x - old.x) + t2 * (updated.y - old.y);
        apply_impulse(a, b, cp.anchor_a.xyz, cp.anchor_b.xyz, p);
    }
    return all_slide;
}

// One pass over the constraint: non-penetration, the tilt rows of a face patch, friction,
// then for a face patch that does not slide at every point its non-penetration and tilt rows
// once more, so the pass ends with the patch's rotation held against the friction rows'
// torque (solve_contact on the CPU, which says why). Without `friction` (the biased passes of
// FrictionPasses::RelaxOnly) the pass ends after the first tilt rows.
fn solve_points(
    c: ptr<function, GpuConstraint>,
    a: ptr<function, BodySim>,
    b: ptr<function, BodySim>,
    use_bias: bool,
    inv_h: f32,
    max_push_out: f32,
    friction: bool,
) {
    let has_patch = (*c).patch_radius > 0.0;
    solve_normal_points(c, a, b, use_bias, inv_h, max_push_out);
    if has_patch {
        solve_tilt(c, a, b);
    }
    if !friction || !ENABLE_FRICTION || (*c).normal.w == 0.0 {
        return;
    }
    let all_slide = solve_friction_points(c, a, b);
    if has_patch && !all_slide {
        solve_normal_points(c, a, b, use_bias, inv_h, max_push_out);
        solve_tilt(c, a, b);
    }
}

// Restitution after the substeps: points that approached faster than `threshold` and pushed
// get a normal velocity of -restitution * approach speed (restitution_contact).
fn restitution_points(c: ptr<function, GpuConstraint>, a: ptr<function, BodySim>, b: ptr<function, BodySim>, threshold: f32) {
    let restitution = (*c).tangent1.w;
    if restitution == 0.0 {
        return;
    }
    let normal = (*c).normal.xyz;
    for (var i = 0u; i < MAX_MANIFOLD_POINTS; i++) {
        if i >= (*c).point_count {
            break;
        }
        let cp = (*c).points[i];
        if cp.relative_velocity > -threshold || cp.total_normal_impulse == 0.0 {
            continue;
        }
        let vn = dot(relative_velocity(*a, *b, cp.anchor_a.xyz, cp.anchor_b.xyz), normal);
        let delta = -cp.anchor_b.w * (vn + restitution * cp.relative_velocity);
        let accumulated = max(cp.normal_impulse + delta, 0.0);
        let applied = accumulated - cp.normal_impulse;
        (*c).points[i].normal_impulse = accumulated;
        (*c).points[i].total_normal_impulse += applied;
        apply_impulse(a, b, cp.anchor_a.xyz, cp.anchor_b.xyz, normal * applied);
    }
}

// The constraint's tilt impulse kept for the next step, with the normal in A's frame
// (`rotation_a`: A's rotation at the start of the step, when the manifold was made).
fn stored_tilt(c: GpuConstraint, rotation_a: vec4<f32>) -> GpuTilt {
    let impulse = c.tangent1.xyz * c.tilt_impulse_1 + c.tangent2.xyz * c.tilt_impulse_2;
    let local = quat_rotate(quat_conjugate(rotation_a), c.normal.xyz);
    return GpuTilt(vec4<f32>(impulse, 0.0), vec4<f32>(local, 0.0));
}

// Point i of a contact with the constraint's final impulses, for the next step's warm start.
fn stored_point(c: GpuConstraint, i: u32, point: GpuContact) -> GpuContact {
    let cp = c.points[i];
    var out = point;
    out.normal_impulse = cp.normal_impulse;
    out.friction_impulse = vec4<f32>(c.tangent1.xyz * cp.tangent_impulse_1 + c.tangent2.xyz * cp.tangent_impulse_2, cp.total_normal_impulse);
    return out;
}
