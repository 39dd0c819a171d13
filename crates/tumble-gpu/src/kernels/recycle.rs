//! Contact recycling in `collide_cuboids` (`shaders/common/recycle.wgsl`): a pair whose bodies
//! barely moved relative to each other since its manifold was last computed keeps it. The CPU
//! twin is tumble-solver's own rule, `CachedManifold::recycle` with `recycle_tolerance`, fed
//! by [`cached_anchors`], which rebuilds the contact cache's anchors from what the GPU keeps
//! per pair slot (a [`GpuLocalManifold`]: points and depths in A's frame, B's frame in A's).

use tumble_geometry::{Manifold, Pose, Rot, nalgebra::Quaternion};
use tumble_solver::{CachedManifold, recycle_tolerance};

use super::collide_cuboids::kind_from_code;
use super::{cuboid_from_gpu, gpu_pair_margin};
use crate::MAX_MANIFOLD_POINTS;
use crate::layout::{GpuContact, GpuLocalManifold, GpuManifold, GpuPose, GpuShape, GpuVelocity};
use crate::solver::convert::{pose_from_gpu, vec3};

/// The contact cache's entry for last step's manifold `m` (its points `points`, its frame-A
/// record `local`): ids, kind and feature, and the anchors `CachedManifold::recycle` moves
/// with the bodies. Point `i`'s anchor on A is its point moved half its depth along the
/// normal, its anchor on B the point moved half the depth back, in B's frame at the poses the
/// manifold was found at (as `CachedManifold::of` puts them). Impulses are left at zero.
pub fn cached_anchors(
    m: &GpuManifold,
    points: &[GpuContact],
    local: &GpuLocalManifold,
) -> CachedManifold {
    let [x, y, z, w] = local.frame_rotation;
    let back = Rot::new_unchecked(Quaternion::new(w, x, y, z)).inverse();
    let origin_b = vec3(&local.frame_position);
    let normal = vec3(&local.normal);
    let mut out = CachedManifold {
        kind: kind_from_code(m.kind),
        feature: m.feature,
        local_normal: normal,
        normal_b: back * normal,
        len: m.len.min(MAX_MANIFOLD_POINTS) as u8,
        ..Default::default()
    };
    let len = out.len as usize;
    for (i, (point, c)) in local.points.iter().zip(points).enumerate().take(len) {
        let half = normal * (0.5 * point[3]);
        let p = vec3(point);
        out.ids[i] = c.id;
        out.local_points[i] = p;
        out.anchors_a[i] = p + half;
        out.anchors_b[i] = back * (p - half - origin_b);
        if point[3] >= 0.0 {
            out.overlapped |= 1 << i;
        }
    }
    out
}

/// Last step's manifold of pair `(a, b)` (`old` with points `points` and frame-A record
/// `local`) reused at this step's poses, as `collide_cuboids` decides with recycling at
/// `recycle_distance` (m), margin `margin` and step `dt`: `tumble_solver::CachedManifold::
/// recycle` at the pair's speculative margin and [`recycle_tolerance`]. `None` when the pair
/// needs a fresh manifold.
#[allow(clippy::too_many_arguments)]
pub fn recycle_gpu_pair(
    poses: &[GpuPose],
    velocities: &[GpuVelocity],
    shapes: &[GpuShape],
    (a, b): (u32, u32),
    (old, points, local): (&GpuManifold, &[GpuContact], &GpuLocalManifold),
    recycle_distance: f32,
    margin: f32,
    dt: f32,
) -> Option<Manifold> {
    let margin = gpu_pair_margin(velocities, shapes, (a, b), margin, dt);
    let (a, b) = (a as usize, b as usize);
    let tolerance = recycle_tolerance(
        recycle_distance,
        &cuboid_from_gpu(&shapes[a]),
        &cuboid_from_gpu(&shapes[b]),
    );
    let (pose_a, pose_b): (Pose, Pose) = (pose_from_gpu(&poses[a]), pose_from_gpu(&poses[b]));
    cached_anchors(old, points, local).recycle(&pose_a, &pose_b, margin, tolerance)
}
