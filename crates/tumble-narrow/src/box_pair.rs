//! Two boxes seen from the first one's frame: every SAT quantity is computed there.
//!
//! Using the delta position `pose_b.t - pose_a.t` before rotating keeps the digits that two boxes
//! far from the origin share: in world space each coordinate would carry the round-off of the
//! absolute position, in A's frame only that of the offset.

use tumble_geometry::{Cuboid, Mat3, Point3, Pose, Real, Vec3};

/// Box B expressed in box A's local frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxPair {
    /// Box A (the frame's owner).
    pub a: Cuboid,
    /// Box B.
    pub b: Cuboid,
    /// B's rotation in A's frame: column `j` is B's local axis `j`.
    pub rot: Mat3,
    /// Entry-wise absolute value of `rot` (the projection radii use it).
    pub abs_rot: Mat3,
    /// B's centre in A's frame.
    pub offset: Vec3,
}

impl BoxPair {
    /// The pair `(a at pose_a, b at pose_b)` seen from A's frame.
    pub fn new(a: &Cuboid, pose_a: &Pose, b: &Cuboid, pose_b: &Pose) -> Self {
        let relative = pose_a.rotation.inverse() * pose_b.rotation;
        let rot = *relative.to_rotation_matrix().matrix();
        let delta = pose_b.translation.vector - pose_a.translation.vector;
        let offset = pose_a.rotation.inverse_transform_vector(&delta);
        Self::from_parts(*a, *b, rot, offset)
    }

    fn from_parts(a: Cuboid, b: Cuboid, rot: Mat3, offset: Vec3) -> Self {
        Self {
            a,
            b,
            rot,
            abs_rot: rot.abs(),
            offset,
        }
    }

    /// The same pair seen from B's frame, with the roles of A and B exchanged.
    pub fn swapped(&self) -> Self {
        let rot_t = self.rot.transpose();
        Self::from_parts(self.b, self.a, rot_t, -(rot_t * self.offset))
    }

    /// A point of B's local frame, in A's frame.
    pub fn b_to_a(&self, p: &Point3) -> Point3 {
        Point3::from(self.rot * p.coords + self.offset)
    }

    /// A point of A's local frame, in B's frame.
    pub fn a_to_b(&self, p: &Point3) -> Point3 {
        Point3::from(self.rot.tr_mul(&(p.coords - self.offset)))
    }

    /// The length that rounding errors scale with: the largest half extent of either box.
    pub fn noise_scale(&self) -> Real {
        self.a.half_extents.max().max(self.b.half_extents.max())
    }

    /// The length that feature choices scale with: the smaller box's largest half extent (a
    /// tiny box on a huge one must not inherit tolerances sized for the huge one).
    pub fn feature_scale(&self) -> Real {
        self.a.half_extents.max().min(self.b.half_extents.max())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tests::at;
    use tumble_geometry::Rot;

    #[test]
    fn points_map_between_frames_consistently_with_the_world_poses() {
        let a = Cuboid::new(Vec3::new(1.0, 2.0, 3.0));
        let b = Cuboid::new(Vec3::new(0.5, 0.25, 2.0));
        let pose_a = at(100.0, -50.0, 3.0, Rot::from_euler_angles(0.3, -1.1, 2.0));
        let pose_b = at(101.0, -49.5, 2.0, Rot::from_euler_angles(-0.7, 0.2, 0.4));
        let pair = BoxPair::new(&a, &pose_a, &b, &pose_b);
        let p_b = Point3::new(0.3, -0.2, 1.5);
        let world = pose_b * p_b;
        // B-local -> A-local must equal B-local -> world -> A-local; f32 at |x| ~ 100: 1e-4.
        assert!((pair.b_to_a(&p_b) - pose_a.inverse_transform_point(&world)).norm() < 1e-4);
        assert!((pair.a_to_b(&pair.b_to_a(&p_b)) - p_b).norm() < 1e-5);
        let swapped = pair.swapped();
        assert_eq!(swapped.a, b);
        assert!((swapped.b_to_a(&Point3::origin()) - pair.a_to_b(&Point3::origin())).norm() < 1e-5);
    }
}
