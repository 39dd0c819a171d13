//! Conversions between tumble-solver's bodies, states, contacts and constraints and their GPU
//! layouts. Used to upload a scene, to read results back, and by the CPU twins.

use tumble_geometry::nalgebra::{Quaternion, Translation3};
use tumble_geometry::{MAX_MANIFOLD_POINTS, Pose, Rot, Vec3};
use tumble_solver::{Body, BodyKind, BodyState, Contact, ContactConstraint, Locks};

use crate::kernels::collide_cuboids::kind_code as manifold_kind_code;
use crate::layout::{GpuContact, GpuManifold, GpuPose, GpuShape, GpuVelocity};

use super::constants::{
    BODY_DYNAMIC, BODY_FIXED, BODY_KINEMATIC, CONSTRAINT_DYNAMIC_A, CONSTRAINT_DYNAMIC_B,
    LOCK_ROTATION_SHIFT,
};
use super::layout::{GpuBody, GpuConstraint, GpuConstraintPoint, GpuTilt};

/// `v` as a WGSL `vec4<f32>` with `w`.
pub(crate) fn vec4(v: &Vec3, w: f32) -> [f32; 4] {
    [v.x, v.y, v.z, w]
}

/// The `xyz` of a WGSL `vec4<f32>`.
pub(crate) fn vec3(v: &[f32; 4]) -> Vec3 {
    Vec3::new(v[0], v[1], v[2])
}

/// The `GpuBody::kind` code of a body kind.
pub fn kind_code(kind: BodyKind) -> u32 {
    match kind {
        BodyKind::Fixed => BODY_FIXED,
        BodyKind::Dynamic => BODY_DYNAMIC,
        BodyKind::Kinematic => BODY_KINEMATIC,
    }
}

/// The `GpuBody::locks` bits of a body's locks.
pub fn lock_bits(locks: &Locks) -> u32 {
    (0..3).fold(0, |bits, k| {
        bits | (u32::from(locks.translation[k]) << k)
            | (u32::from(locks.rotation[k]) << (k as u32 + LOCK_ROTATION_SHIFT))
    })
}

/// A body's constant solver data.
pub fn gpu_body(body: &Body) -> GpuBody {
    let inverse = body.inverse_inertia_local;
    let inertia = body.inertia_local();
    GpuBody {
        inverse_inertia: vec4(&inverse, body.inverse_mass),
        inertia: vec4(&inertia, 0.0),
        kind: kind_code(body.kind),
        locks: lock_bits(&body.locks),
        friction: body.material.friction,
        restitution: body.material.restitution,
        linear_damping: body.linear_damping,
        angular_damping: body.angular_damping,
        world: 0,
        _pad1: 0,
        force: vec4(&body.force, body.gravity_scale),
        torque: vec4(&body.torque, 0.0),
    }
}

/// A body's shape for the collision stages; bodies contacts cannot move are flagged static
/// (two of them never pair).
pub fn gpu_shape(body: &Body) -> GpuShape {
    GpuShape::cuboid(&body.shape, !body.is_dynamic())
}

/// The host form of a GPU pose (the quaternion is taken as stored; the GPU keeps it unit).
pub fn pose_from_gpu(p: &GpuPose) -> Pose {
    let [x, y, z, _] = p.position;
    let [i, j, k, w] = p.rotation;
    Pose::from_parts(
        Translation3::new(x, y, z),
        Rot::new_unchecked(Quaternion::new(w, i, j, k)),
    )
}

/// A body's velocities in GPU layout.
pub fn gpu_velocity(state: &BodyState) -> GpuVelocity {
    GpuVelocity::new(state.linear_velocity, state.angular_velocity)
}

/// A CPU contact in the collision stages' layout: its manifold (with `previous`, the pair's
/// manifold index in last step's list or `NO_PREVIOUS`) and `MAX_MANIFOLD_POINTS` points
/// carrying its warm-start impulses.
pub fn gpu_manifold(
    contact: &Contact,
    previous: u32,
) -> (GpuManifold, [GpuContact; MAX_MANIFOLD_POINTS]) {
    let m = &contact.manifold;
    let mut points = [GpuContact::default(); MAX_MANIFOLD_POINTS];
    for (slot, (p, j)) in points
        .iter_mut()
        .zip(m.points().iter().zip(&contact.impulses))
    {
        *slot = GpuContact {
            position: vec4(&p.position.coords, 0.0),
            friction_impulse: vec4(&j.friction, 0.0),
            depth: p.depth,
            id: p.id,
            normal_impulse: j.normal,
            _pad: 0,
        };
    }
    let manifold = GpuManifold {
        normal: vec4(&m.normal, 0.0),
        body_a: contact.body_a,
        body_b: contact.body_b,
        kind: manifold_kind_code(m.kind),
        feature: m.feature,
        len: u32::from(m.len),
        previous,
        recycled: u32::from(contact.recycled),
        _pad0: 0,
    };
    (manifold, points)
}

/// Copies the solved impulses of `points` (a manifold's GPU points), the step totals of its
/// constraint and its tilt impulse into `contact`.
pub fn read_impulses(points: &[GpuContact], tilt: &GpuTilt, contact: &mut Contact) {
    contact.tilt_impulse = vec3(&tilt.impulse);
    let n = (contact.manifold.len as usize).min(MAX_MANIFOLD_POINTS);
    for (i, point) in points.iter().take(n).enumerate() {
        contact.impulses[i].normal = point.normal_impulse;
        contact.impulses[i].friction = vec3(&point.friction_impulse);
        // store_impulses puts the step's total there (the GPU reads only xyz).
        contact.total_normal_impulse[i] = point.friction_impulse[3];
    }
}

/// A CPU constraint in GPU layout.
pub fn gpu_constraint(c: &ContactConstraint) -> GpuConstraint {
    let mut points = [GpuConstraintPoint::default(); MAX_MANIFOLD_POINTS];
    for (slot, p) in points.iter_mut().zip(&c.points[..c.point_count as usize]) {
        *slot = GpuConstraintPoint {
            anchor_a: vec4(&p.anchor_a, p.base_separation),
            anchor_b: vec4(&p.anchor_b, p.normal_mass),
            tangent_mass_1: p.tangent_mass[0],
            tangent_mass_2: p.tangent_mass[1],
            normal_impulse: p.normal_impulse,
            total_normal_impulse: p.total_normal_impulse,
            tangent_impulse_1: p.tangent_impulse[0],
            tangent_impulse_2: p.tangent_impulse[1],
            relative_velocity: p.relative_velocity,
            _pad: 0.0,
        };
    }
    let flags = if c.dynamic_a { CONSTRAINT_DYNAMIC_A } else { 0 }
        | if c.dynamic_b { CONSTRAINT_DYNAMIC_B } else { 0 };
    GpuConstraint {
        body_a: c.body_a,
        body_b: c.body_b,
        point_count: c.point_count,
        flags,
        normal: vec4(&c.normal, c.friction),
        tangent1: vec4(&c.tangent1, c.restitution),
        tangent2: vec4(&c.tangent2, c.slop),
        softness: [
            c.softness.bias_rate,
            c.softness.mass_scale,
            c.softness.impulse_scale,
            0.0,
        ],
        tilt_mass_1: c.tilt_mass[0],
        tilt_mass_2: c.tilt_mass[1],
        tilt_impulse_1: c.tilt_impulse[0],
        tilt_impulse_2: c.tilt_impulse[1],
        patch_radius: c.patch_radius,
        _pad0: 0.0,
        _pad1: 0.0,
        _pad2: 0.0,
        points,
    }
}

/// The tilt slot a host-made contact leaves for the next step: its carried tilt impulse and
/// its normal in body A's frame at `pose_a` (so the GPU's normal check passes exactly when the
/// host's warm start already decided to carry it).
pub fn gpu_tilt(contact: &Contact, pose_a: &Pose) -> GpuTilt {
    let local = pose_a
        .rotation
        .inverse_transform_vector(&contact.manifold.normal);
    GpuTilt {
        impulse: vec4(&contact.tilt_impulse, 0.0),
        local_normal: vec4(&local, 0.0),
    }
}
