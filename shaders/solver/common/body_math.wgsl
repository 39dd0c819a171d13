// requires: common/quat.wgsl common/solver_types.wgsl solver/common/solver_constants.wgsl
// Body math of the solver stages as pure functions, mirroring crates/tumble-solver: lock masks
// and the world inverse inertia (body.rs), the implicit-midpoint gyroscopic term
// (gyroscopic.rs), and the integration steps (integrate.rs).

// Newton iterations of the gyroscopic midpoint equation (tumble-solver's NEWTON_ITERATIONS).
override GYROSCOPIC_NEWTON_ITERATIONS: u32;

// The Hamilton product a b of quaternions (x, y, z, w).
fn quat_mul(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}

// The inverse rotation of a unit quaternion.
fn quat_conjugate(q: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(-q.xyz, q.w);
}

// 1 on free world axes, 0 on locked ones, for the three lock bits starting at `shift`.
fn axis_mask(locks: u32, shift: u32) -> vec3<f32> {
    let bits = (vec3<u32>(locks >> shift) >> vec3<u32>(0u, 1u, 2u)) & vec3<u32>(1u);
    return select(vec3<f32>(1.0), vec3<f32>(0.0), bits != vec3<u32>(0u));
}

fn translation_mask(locks: u32) -> vec3<f32> {
    return axis_mask(locks, 0u);
}

// Free rotation axes; none when rotation is compiled out (then no body turns at all).
fn rotation_mask(locks: u32) -> vec3<f32> {
    if !ENABLE_ROTATION {
        return vec3<f32>(0.0);
    }
    return axis_mask(locks, LOCK_ROTATION_SHIFT);
}

// The three rotation lock bits.
fn rotation_locks(locks: u32) -> u32 {
    return (locks >> LOCK_ROTATION_SHIFT) & 7u;
}

fn diagonal(d: vec3<f32>) -> mat3x3<f32> {
    return mat3x3<f32>(vec3<f32>(d.x, 0.0, 0.0), vec3<f32>(0.0, d.y, 0.0), vec3<f32>(0.0, 0.0, d.z));
}

// The world inverse inertia P R D R^T P (Body::inverse_inertia_world): D the local inverse
// moments, P zeroing locked rotation axes; zero when rotation is compiled out.
fn world_inverse_inertia(body: GpuBody, rotation: vec4<f32>) -> mat3x3<f32> {
    let d = body.inverse_inertia.xyz;
    let locked = rotation_locks(body.locks);
    if !ENABLE_ROTATION || locked == 7u || all(d == vec3<f32>(0.0)) {
        return mat3x3<f32>();
    }
    let r = quat_to_mat3(rotation);
    let world = r * diagonal(d) * transpose(r);
    if locked != 0u {
        let p = diagonal(rotation_mask(body.locks));
        return p * world * p;
    }
    return world;
}

// The skew-symmetric matrix with skew(a) b = a x b.
fn skew(a: vec3<f32>) -> mat3x3<f32> {
    return mat3x3<f32>(vec3<f32>(0.0, a.z, -a.y), vec3<f32>(-a.z, 0.0, a.x), vec3<f32>(a.y, -a.x, 0.0));
}

// Advances the body-frame angular velocity w0 by h under the gyroscopic torque of principal
// moments `inertia` with the implicit midpoint rule I (w1 - w0) = h (I wm) x wm (Newton).
fn gyroscopic_midpoint(inertia: vec3<f32>, w0: vec3<f32>, h: f32) -> vec3<f32> {
    let moments = diagonal(inertia);
    var w1 = w0;
    for (var k = 0u; k < GYROSCOPIC_NEWTON_ITERATIONS; k++) {
        let wm = (w0 + w1) * 0.5;
        let lm = inertia * wm;
        let residual = inertia * (w1 - w0) - cross(lm, wm) * h;
        let jacobian = moments - (skew(lm) - skew(wm) * moments) * (0.5 * h);
        // Inverse by cofactors: the rows of J^-1 are the cross products of J's columns.
        let r0 = cross(jacobian[1], jacobian[2]);
        let det = dot(jacobian[0], r0);
        if det == 0.0 {
            break;
        }
        let cofactors = mat3x3<f32>(r0, cross(jacobian[2], jacobian[0]), cross(jacobian[0], jacobian[1]));
        w1 -= (transpose(cofactors) * (1.0 / det)) * residual;
    }
    return w1;
}

// A body's solver state at the start of a step: no delta yet, masses in world axes.
fn prepare_body(body: GpuBody, pose: GpuPose) -> GpuSolverBody {
    let inverse_inertia = world_inverse_inertia(body, pose.rotation);
    return GpuSolverBody(
        vec4<f32>(0.0),
        vec4<f32>(0.0, 0.0, 0.0, 1.0),
        vec4<f32>(translation_mask(body.locks) * body.inverse_inertia.w, 0.0),
        vec4<f32>(inverse_inertia[0], 0.0),
        vec4<f32>(inverse_inertia[1], 0.0),
        vec4<f32>(inverse_inertia[2], 0.0),
    );
}

// Half of a substep's gyroscopic update (the implicit midpoint rule over h / 2), split around
// the rotation update as on the CPU (gyroscopic_half_step): the rotation turns with the
// angular velocity of mid-substep, keeping a free body's world angular momentum to second
// order. `rotation` is the body's current world rotation. Locked bodies skip the term (it
// would need the lock's reaction torque); equal moments make it zero.
fn gyroscopic_half_step(body: GpuBody, rotation: vec4<f32>, w: vec3<f32>, h: f32) -> vec3<f32> {
    let inertia = body.inertia.xyz;
    let symmetric = inertia.x == inertia.y && inertia.y == inertia.z;
    if !ENABLE_ROTATION || symmetric || rotation_locks(body.locks) != 0u || all(w == vec3<f32>(0.0)) {
        return w;
    }
    let local = quat_rotate(quat_conjugate(rotation), w);
    return quat_rotate(rotation, gyroscopic_midpoint(inertia, local, 0.5 * h));
}

// integrate_velocities for one body: gravity times the body's gravity scale, its force and
// torque, the first half of the gyroscopic update, damping, locks (integrate.rs, in the same
// order). Fixed and kinematic bodies keep their velocity. `state` is the body's solver state:
// its rotation delta, and its world inverse inertia at the start of the step.
fn integrate_velocity(
    body: GpuBody,
    rotation: vec4<f32>,
    state: GpuSolverBody,
    velocity: GpuVelocity,
    gravity: vec3<f32>,
    h: f32,
) -> GpuVelocity {
    if body.kind != BODY_DYNAMIC {
        return velocity;
    }
    let linear_damping = 1.0 / (1.0 + h * body.linear_damping);
    let angular_damping = 1.0 / (1.0 + h * body.angular_damping);
    var v = velocity.linear.xyz;
    if ENABLE_GRAVITY {
        // g * 1.0 is g exactly: the default scale keeps the unscaled step's bits.
        v = v + (gravity * body.force.w) * h;
    }
    // Skipped, not added as zero, without a force (-0 + 0 is +0), as on the CPU.
    let force = body.force.xyz;
    if any(force != vec3<f32>(0.0)) {
        v = v + force * (body.inverse_inertia.w * h);
    }
    v = v * linear_damping;
    var w0 = velocity.angular.xyz;
    let torque = body.torque.xyz;
    if ENABLE_ROTATION && any(torque != vec3<f32>(0.0)) {
        let inverse_inertia = mat3x3<f32>(
            state.inverse_inertia_x.xyz,
            state.inverse_inertia_y.xyz,
            state.inverse_inertia_z.xyz,
        );
        w0 = w0 + inverse_inertia * (torque * h);
    }
    var w = gyroscopic_half_step(body, quat_mul(state.delta_rotation, rotation), w0, h);
    w = w * angular_damping;
    return GpuVelocity(
        vec4<f32>(v * translation_mask(body.locks), 0.0),
        vec4<f32>(w * rotation_mask(body.locks), 0.0),
    );
}

// integrate_positions for one body: clamps a dynamic body's speeds, advances its deltas by h
// (dp += h v, dq += h/2 (w, 0) dq, renormalized), then applies the second half of a dynamic
// body's gyroscopic update. `rotation` is the pose's rotation at the start of the step. Fixed
// bodies do not move.
fn integrate_position(
    body: GpuBody,
    rotation: vec4<f32>,
    velocity: ptr<function, GpuVelocity>,
    state: ptr<function, GpuSolverBody>,
    h: f32,
) {
    let kind = body.kind;
    if kind == BODY_FIXED {
        return;
    }
    var v = (*velocity).linear.xyz;
    var w = (*velocity).angular.xyz;
    if kind == BODY_DYNAMIC {
        let max_angular = MAX_ROTATION_PER_SUBSTEP / h;
        let w_norm = length(w);
        if w_norm > max_angular {
            w = w * (max_angular / w_norm);
        }
        let v_norm = length(v);
        if v_norm > MAX_LINEAR_SPEED {
            v = v * (MAX_LINEAR_SPEED / v_norm);
        }
        (*velocity).linear = vec4<f32>(v, 0.0);
        (*velocity).angular = vec4<f32>(w, 0.0);
    }
    (*state).delta_position = vec4<f32>((*state).delta_position.xyz + v * h, 0.0);
    if ENABLE_ROTATION && any(w != vec3<f32>(0.0)) {
        let q = (*state).delta_rotation;
        let spin = quat_mul(vec4<f32>(w, 0.0), q) * (0.5 * h);
        (*state).delta_rotation = normalize(q + spin);
    }
    if kind == BODY_DYNAMIC {
        let turned = quat_mul((*state).delta_rotation, rotation);
        (*velocity).angular = vec4<f32>(gyroscopic_half_step(body, turned, (*velocity).angular.xyz, h), 0.0);
    }
}

// The pose at the end of the step: c += dp, q = normalize(dq q). Fixed bodies keep theirs.
fn finalize_pose(kind: u32, pose: GpuPose, state: GpuSolverBody) -> GpuPose {
    if kind == BODY_FIXED {
        return pose;
    }
    let position = pose.position.xyz + state.delta_position.xyz;
    let rotation = normalize(quat_mul(state.delta_rotation, pose.rotation));
    return GpuPose(vec4<f32>(position, pose.position.w), rotation);
}
