//! Stage 1, `update_aabbs`: each box's AABB for the step, grown so that every pair that can
//! meet within the step is found by the broad phase.
//!
//! The functions take plain slices (shapes, poses, velocities), so the CPU step and the GPU
//! backend's reference twin call the same code.

use tumble_geometry::{Aabb, Cuboid, Pose, Real, Vec3};

/// The AABB of one box for the step: its world AABB grown by `margin` on all sides,
/// stretched by `linear * dt` in the direction of motion, and grown by `|angular| r dt` (the
/// farthest a corner at radius `r = |half_extents|` can turn in the step).
#[inline]
pub fn motion_aabb(
    shape: &Cuboid,
    pose: &Pose,
    linear: &Vec3,
    angular: &Vec3,
    margin: Real,
    dt: Real,
) -> Aabb {
    let mut aabb = shape.aabb(pose, margin);
    let travel = linear * dt;
    let turn = angular.norm() * shape.half_extents.norm() * dt;
    for i in 0..3 {
        aabb.min[i] += travel[i].min(0.0) - turn;
        aabb.max[i] += travel[i].max(0.0) + turn;
    }
    aabb
}

/// [`motion_aabb`] of every box: `shapes`, `poses`, `linear` and `angular` velocities are
/// parallel slices (the result is as long as the shortest).
pub fn update_aabbs(
    shapes: &[Cuboid],
    poses: &[Pose],
    linear: &[Vec3],
    angular: &[Vec3],
    margin: Real,
    dt: Real,
) -> Vec<Aabb> {
    shapes
        .iter()
        .zip(poses)
        .zip(linear.iter().zip(angular))
        .map(|((shape, pose), (v, w))| motion_aabb(shape, pose, v, w, margin, dt))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_geometry::Rot;

    #[test]
    fn a_still_box_gets_its_margin_only() {
        let shape = Cuboid::new(Vec3::new(1.0, 0.5, 0.25));
        let pose = Pose::translation(1.0, 2.0, 3.0);
        let a = motion_aabb(&shape, &pose, &Vec3::zeros(), &Vec3::zeros(), 0.5, 0.1);
        assert_eq!(a.min, tumble_geometry::Point3::new(-0.5, 1.0, 2.25));
        assert_eq!(a.max, tumble_geometry::Point3::new(2.5, 3.0, 3.75));
    }

    #[test]
    fn travel_stretches_one_side_and_spin_grows_both() {
        // Half extents (0, 3, 4): radius 5. Spin 2 rad/s over dt 0.5 turns a corner 5 m.
        let shape = Cuboid::new(Vec3::new(0.0, 3.0, 4.0));
        let pose = Pose::identity();
        let v = Vec3::new(4.0, -2.0, 0.0);
        let w = Vec3::new(0.0, 2.0, 0.0);
        let a = motion_aabb(&shape, &pose, &v, &w, 0.0, 0.5);
        assert_eq!(a.min, tumble_geometry::Point3::new(-5.0, -9.0, -9.0));
        assert_eq!(a.max, tumble_geometry::Point3::new(7.0, 8.0, 9.0));
    }

    #[test]
    fn the_slice_form_equals_the_single_box_form() {
        let shapes = [
            Cuboid::new(Vec3::new(0.5, 0.5, 0.5)),
            Cuboid::new(Vec3::new(1.0, 0.2, 0.3)),
        ];
        let poses = [
            Pose::translation(0.0, 1.0, 0.0),
            Pose::from_parts(
                tumble_geometry::Point3::new(3.0, 0.0, -1.0).into(),
                Rot::from_euler_angles(0.3, 0.2, 0.1),
            ),
        ];
        let linear = [Vec3::new(0.0, -3.0, 0.0), Vec3::new(1.0, 0.0, 2.0)];
        let angular = [Vec3::zeros(), Vec3::new(0.5, 0.0, 0.0)];
        let all = update_aabbs(&shapes, &poses, &linear, &angular, 0.02, 1.0 / 60.0);
        assert_eq!(all.len(), 2);
        for i in 0..2 {
            let one = motion_aabb(
                &shapes[i],
                &poses[i],
                &linear[i],
                &angular[i],
                0.02,
                1.0 / 60.0,
            );
            assert_eq!(all[i], one);
        }
        // Falling at 3 m/s for 1/60 s: the bottom drops a further 5 cm below the margin.
        assert!((all[0].min.y - (0.5 - 0.02 - 0.05)).abs() < 1e-6);
        assert!((all[0].max.y - (1.5 + 0.02)).abs() < 1e-6);
    }
}
