//! `update_aabbs`: poses -> world AABBs grown by the speculative margin and swept by the
//! motion over the next step.

use tumble_geometry::{Aabb, Cuboid, Point3, Pose, Rot, Vec3};

use crate::kernel::kernel;
use crate::layout::{GpuAabb, GpuPose, GpuShape, GpuVelocity};

kernel! {
    /// Buffers of [`UPDATE_AABBS`].
    pub struct UpdateAabbsArgs {
        /// [`crate::layout::UpdateAabbsParams`].
        params,
        /// `array<GpuPose>`, one per body.
        poses,
        /// `array<GpuVelocity>`, one per body.
        velocities,
        /// `array<GpuShape>`, one per body.
        shapes,
        /// Output `array<GpuAabb>`, one per body.
        aabbs,
    }
    /// The kernel: one thread per body.
    pub static UPDATE_AABBS = "update_aabbs.wgsl";
}

/// The host form of a GPU pose.
pub fn pose_from_gpu(p: &GpuPose) -> Pose {
    let [x, y, z, _] = p.position;
    let [i, j, k, w] = p.rotation;
    Pose::from_parts(
        tumble_geometry::nalgebra::Translation3::new(x, y, z),
        Rot::new_unchecked(tumble_geometry::nalgebra::Quaternion::new(w, i, j, k)),
    )
}

/// The CPU twin of [`UPDATE_AABBS`]: [`Aabb::from_cuboid`] grown by the margin, plus the
/// rotation bound `|w| |h| dt` on every side and the linear sweep `v dt` on its side.
pub fn update_aabbs_cpu(
    poses: &[GpuPose],
    velocities: &[GpuVelocity],
    shapes: &[GpuShape],
    margin: f32,
    dt: f32,
) -> Vec<GpuAabb> {
    poses
        .iter()
        .zip(velocities)
        .zip(shapes)
        .map(|((p, v), s)| {
            let h = Vec3::new(s.hx, s.hy, s.hz);
            let w = Vec3::new(v.angular[0], v.angular[1], v.angular[2]);
            let spin = w.norm() * h.norm() * dt;
            let tight = Aabb::from_cuboid(&Cuboid::new(h), &pose_from_gpu(p), margin + spin);
            let travel = Vec3::new(v.linear[0], v.linear[1], v.linear[2]) * dt;
            let lo: Point3 = tight.min + travel.inf(&Vec3::zeros());
            let hi: Point3 = tight.max + travel.sup(&Vec3::zeros());
            GpuAabb {
                min: [lo.x, lo.y, lo.z, 0.0],
                max: [hi.x, hi.y, hi.z, 0.0],
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn at_rest_the_box_is_the_geometry_layers_box_and_motion_only_grows_it() {
        let pose = Pose::from_parts(
            tumble_geometry::nalgebra::Translation3::new(1.0, -2.0, 3.0),
            Rot::from_euler_angles(0.3, -0.2, 1.1),
        );
        let cuboid = Cuboid::new(Vec3::new(0.5, 0.2, 0.9));
        let shape = [crate::layout::GpuShape::cuboid(&cuboid, false)];
        let poses = [GpuPose::from_pose(&pose)];
        let rest = update_aabbs_cpu(&poses, &[GpuVelocity::default()], &shape, 0.02, 0.1)[0];
        let tight = Aabb::from_cuboid(&cuboid, &pose, 0.02);
        for k in 0..3 {
            assert_eq!(rest.min[k], tight.min[k]);
            assert_eq!(rest.max[k], tight.max[k]);
        }
        // Moving at +3 m/s along x for 0.1 s stretches the box 0.3 m on the +x side only.
        let moving = GpuVelocity::new(Vec3::new(3.0, 0.0, 0.0), Vec3::zeros());
        let swept = update_aabbs_cpu(&poses, &[moving], &shape, 0.02, 0.1)[0];
        assert!((swept.max[0] - rest.max[0] - 0.3).abs() < 1e-6);
        assert_eq!(swept.min[0], rest.min[0]);
        // Spinning at 2 rad/s grows every side by |w| |h| dt.
        let spinning = GpuVelocity::new(Vec3::zeros(), Vec3::new(0.0, 2.0, 0.0));
        let spun = update_aabbs_cpu(&poses, &[spinning], &shape, 0.02, 0.1)[0];
        let grow = 2.0 * cuboid.half_extents.norm() * 0.1;
        for k in 0..3 {
            assert!((rest.min[k] - spun.min[k] - grow).abs() < 1e-5);
        }
    }
}
