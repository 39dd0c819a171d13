//! Penetration depth of two oriented boxes, by the separating-axis theorem, for judging
//! scene outcomes independently of any engine's narrow phase.

use tumble_geometry::{Cuboid, Pose, Real, Vec3};

/// Edge-edge axes shorter than this (squared length of the cross product of unit vectors)
/// come from nearly parallel edges: their direction is noise, and the face axes already
/// bound the overlap there.
const PARALLEL_EPSILON_SQ: Real = 1e-10;

/// How deep two boxes overlap: the smallest overlap of their projections over the 15 SAT
/// axes (3 face normals of each, 9 edge cross products). Zero or negative means separated
/// (the value is then minus the gap along the best separating axis).
pub fn cuboid_penetration(a: &Cuboid, pose_a: &Pose, b: &Cuboid, pose_b: &Pose) -> Real {
    let ra = pose_a.rotation.to_rotation_matrix();
    let rb = pose_b.rotation.to_rotation_matrix();
    let axes_a: [Vec3; 3] = std::array::from_fn(|k| ra.matrix().column(k).into_owned());
    let axes_b: [Vec3; 3] = std::array::from_fn(|k| rb.matrix().column(k).into_owned());
    let d = pose_b.translation.vector - pose_a.translation.vector;
    let radius = |axes: &[Vec3; 3], h: &Vec3, n: &Vec3| -> Real {
        (0..3).map(|k| h[k] * axes[k].dot(n).abs()).sum()
    };
    let overlap = |n: &Vec3| -> Real {
        radius(&axes_a, &a.half_extents, n) + radius(&axes_b, &b.half_extents, n) - d.dot(n).abs()
    };
    let mut depth = Real::INFINITY;
    for n in axes_a.iter().chain(axes_b.iter()) {
        depth = depth.min(overlap(n));
    }
    for ea in &axes_a {
        for eb in &axes_b {
            let n = ea.cross(eb);
            let len_sq = n.norm_squared();
            if len_sq > PARALLEL_EPSILON_SQ {
                depth = depth.min(overlap(&(n / len_sq.sqrt())));
            }
        }
    }
    depth
}
