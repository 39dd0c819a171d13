//! `carry_impulses`: last step's impulses onto this step's points, by feature id and, where
//! ids changed, by position in body A's frame (the CPU contact cache's rule); it also keeps
//! each manifold in A's frame for the next step.

use tumble_geometry::Vec3;

use crate::MAX_MANIFOLD_POINTS;
use crate::constants::{NO_PREVIOUS, PERSIST_DISTANCE};
use crate::kernel::KernelSpec;
use crate::layout::{GpuContact, GpuLocalManifold, GpuManifold, GpuPose};
use crate::shader::file;
use crate::solver::constants::PERSIST_NORMAL_COS;
use crate::solver::convert::{vec3, vec4};

/// The kernel: one thread per manifold.
pub static CARRY_IMPULSES: KernelSpec = KernelSpec::new(file("carry_impulses.wgsl"));

/// What last step left for [`carry_impulses_cpu`]: its manifolds, their points with the
/// solver's impulses, and the manifolds in body A's frame, all indexed by last step's slot.
#[derive(Clone, Copy, Debug)]
pub struct CarryHistory<'a> {
    /// Last step's manifolds.
    pub manifolds: &'a [GpuManifold],
    /// Last step's points, `MAX_MANIFOLD_POINTS` per manifold.
    pub contacts: &'a [GpuContact],
    /// Last step's manifolds in A's frame.
    pub locals: &'a [GpuLocalManifold],
}

/// `v` rotated by the inverse of the unit quaternion `q = (x, y, z, w)`, in the shader's
/// two-cross-product form (`quat_rotate` of the conjugate of `q`), so the twin rounds alike.
fn rotate_inverse(q: [f32; 4], v: Vec3) -> Vec3 {
    let axis = -Vec3::new(q[0], q[1], q[2]);
    let t = 2.0 * axis.cross(&v);
    v + q[3] * t + axis.cross(&t)
}

/// The product `conj(a) b` of unit quaternions `(x, y, z, w)` (B's rotation in A's frame), in
/// the shader's `quat_mul(quat_conjugate(a), b)` form.
fn relative_rotation(a: [f32; 4], b: [f32; 4]) -> [f32; 4] {
    let (av, aw) = (-Vec3::new(a[0], a[1], a[2]), a[3]);
    let (bv, bw) = (Vec3::new(b[0], b[1], b[2]), b[3]);
    let v = aw * bv + bw * av + av.cross(&bv);
    vec4(&v, aw * bw - av.dot(&bv))
}

/// Manifold `m` (points `points`) in the frame of body A at pose `a`: normal, points with
/// their depths, and B's frame (pose `b`) in A's.
fn local_manifold(
    m: &GpuManifold,
    points: &[GpuContact],
    a: &GpuPose,
    b: &GpuPose,
) -> GpuLocalManifold {
    let mut out = GpuLocalManifold {
        normal: vec4(&rotate_inverse(a.rotation, vec3(&m.normal)), 0.0),
        frame_rotation: relative_rotation(a.rotation, b.rotation),
        frame_position: vec4(
            &rotate_inverse(a.rotation, vec3(&b.position) - vec3(&a.position)),
            0.0,
        ),
        ..Default::default()
    };
    for (slot, p) in out.points.iter_mut().zip(points) {
        let local = rotate_inverse(a.rotation, vec3(&p.position) - vec3(&a.position));
        *slot = vec4(&local, p.depth);
    }
    out
}

/// Gives `points` (manifold `m`, in A's frame `here`) last step's impulses from the old
/// manifold `old` (points `before`, in A's frame `old_local`).
fn carry_manifold(
    m: &GpuManifold,
    points: &mut [GpuContact],
    here: &GpuLocalManifold,
    old: &GpuManifold,
    before: &[GpuContact],
    old_local: &GpuLocalManifold,
) {
    let inherit = |p: &mut GpuContact, b: &GpuContact| {
        p.normal_impulse = b.normal_impulse;
        p.friction_impulse = b.friction_impulse;
    };
    let mut claimed = [false; MAX_MANIFOLD_POINTS as usize];
    let mut matched = [false; MAX_MANIFOLD_POINTS as usize];
    if old.kind == m.kind && old.feature == m.feature {
        for (i, p) in points.iter_mut().enumerate() {
            if let Some(j) = (0..before.len()).find(|&j| !claimed[j] && before[j].id == p.id) {
                inherit(p, &before[j]);
                claimed[j] = true;
                matched[i] = true;
            }
        }
    }
    if vec3(&here.normal).dot(&vec3(&old_local.normal)) < PERSIST_NORMAL_COS {
        return;
    }
    let limit = PERSIST_DISTANCE * PERSIST_DISTANCE;
    for (i, p) in points.iter_mut().enumerate() {
        if matched[i] {
            continue;
        }
        let local = vec3(&here.points[i]);
        let nearest = (0..before.len())
            .filter(|&j| !claimed[j])
            .map(|j| (j, (vec3(&old_local.points[j]) - local).norm_squared()))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((j, d2)) = nearest
            && d2 <= limit
        {
            inherit(p, &before[j]);
            claimed[j] = true;
        }
    }
}

/// The CPU twin of [`CARRY_IMPULSES`], in place on `contacts` (the CPU contact cache's rule:
/// under the same kind and feature by id, then by position within [`PERSIST_DISTANCE`] while
/// the normal turned by less than the angle of [`PERSIST_NORMAL_COS`]). Returns this step's
/// manifolds in A's frame, one per manifold (zero where it has no points; a recycled one's is
/// the one it was recycled from), the next step's `previous.locals`.
pub fn carry_impulses_cpu(
    poses: &[GpuPose],
    manifolds: &[GpuManifold],
    contacts: &mut [GpuContact],
    previous: &CarryHistory<'_>,
) -> Vec<GpuLocalManifold> {
    let per = MAX_MANIFOLD_POINTS as usize;
    let mut locals = vec![GpuLocalManifold::default(); manifolds.len()];
    for (k, m) in manifolds.iter().enumerate() {
        if m.len == 0 {
            continue;
        }
        let points = &mut contacts[k * per..k * per + m.len as usize];
        let here = local_manifold(
            m,
            points,
            &poses[m.body_a as usize],
            &poses[m.body_b as usize],
        );
        locals[k] = if m.recycled != 0 {
            previous.locals[m.previous as usize]
        } else {
            here
        };
        if m.previous == NO_PREVIOUS {
            continue;
        }
        let prev = m.previous as usize;
        let old = &previous.manifolds[prev];
        if old.len == 0 {
            continue;
        }
        let before = &previous.contacts[prev * per..prev * per + old.len as usize];
        carry_manifold(m, points, &here, old, before, &previous.locals[prev]);
    }
    locals
}

#[cfg(test)]
mod tests {
    use super::*;

    fn manifold(kind: u32, feature: u32, len: u32, previous: u32) -> GpuManifold {
        GpuManifold {
            normal: [0.0, 1.0, 0.0, 0.0],
            kind,
            feature,
            len,
            previous,
            ..Default::default()
        }
    }

    /// A point with id `id` at `x` along the x axis.
    fn point(id: u32, x: f32, impulse: f32) -> GpuContact {
        GpuContact {
            position: [x, 0.0, 0.0, 0.0],
            id,
            normal_impulse: impulse,
            ..Default::default()
        }
    }

    /// The identity pose: world and A's frame coincide.
    fn poses() -> Vec<GpuPose> {
        vec![GpuPose {
            rotation: [0.0, 0.0, 0.0, 1.0],
            ..Default::default()
        }]
    }

    #[test]
    fn impulses_follow_ids_under_the_same_feature_then_positions_within_a_centimetre() {
        let per = MAX_MANIFOLD_POINTS as usize;
        let mut before = vec![GpuContact::default(); 2 * per];
        // Old points 10 cm apart, so at most one lies within the 1 cm reach of a new point.
        before[0] = point(10, 0.0, 1.0);
        before[1] = point(11, 0.1, 2.0);
        before[2] = point(12, 0.2, 3.0);
        before[per] = point(10, 0.0, 5.0);
        let old = [
            manifold(0, 2, 3, NO_PREVIOUS),
            manifold(0, 3, 1, NO_PREVIOUS),
        ];
        let old_locals = carry_impulses_cpu(
            &poses(),
            &old,
            &mut before.clone(),
            &CarryHistory {
                manifolds: &[],
                contacts: &[],
                locals: &[],
            },
        );
        // Manifold 0 continues old 0 (same face 2): id 11 matches by id though it moved 3 cm,
        // id 99 sits 4 mm from old id 12 (taken by position), id 98 sits 4 mm from old id 10,
        // which the new id 10 claims by id first, leaving no old point: it starts at zero.
        // Manifold 1 continues old 1 on another face: its id means another feature, but the
        // point did not move, so it inherits by position.
        let now = [manifold(0, 2, 4, 0), manifold(0, 4, 1, 1)];
        let mut contacts = vec![GpuContact::default(); 2 * per];
        contacts[0] = point(11, 0.13, 0.0);
        contacts[1] = point(99, 0.204, 0.0);
        contacts[2] = point(98, 0.004, 0.0);
        contacts[3] = point(10, 0.0, 0.0);
        contacts[per] = point(10, 0.0, 0.0);
        let history = CarryHistory {
            manifolds: &old,
            contacts: &before,
            locals: &old_locals,
        };
        let locals = carry_impulses_cpu(&poses(), &now, &mut contacts, &history);
        let got: Vec<f32> = [0, 1, 2, 3, per]
            .iter()
            .map(|&i| contacts[i].normal_impulse)
            .collect();
        assert_eq!(got, [2.0, 3.0, 0.0, 1.0, 5.0]);
        assert_eq!(locals[0].points[1], [0.204, 0.0, 0.0, 0.0]);

        // A normal turned by 10 degrees (past the 5 degree limit): only ids carry.
        let turn = 10f32.to_radians();
        let mut tilted = now;
        for m in &mut tilted {
            m.normal = [turn.sin(), turn.cos(), 0.0, 0.0];
        }
        let mut contacts2 = vec![GpuContact::default(); 2 * per];
        contacts2[..4].copy_from_slice(&contacts[..4]);
        contacts2[per] = contacts[per];
        for c in &mut contacts2 {
            c.normal_impulse = 0.0;
        }
        carry_impulses_cpu(&poses(), &tilted, &mut contacts2, &history);
        let got: Vec<f32> = [0, 1, 2, 3, per]
            .iter()
            .map(|&i| contacts2[i].normal_impulse)
            .collect();
        assert_eq!(got, [2.0, 0.0, 0.0, 1.0, 0.0]);
    }
}
