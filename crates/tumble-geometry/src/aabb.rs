//! Axis-aligned bounding boxes.

use crate::{Cuboid, Point3, Pose, Real};

/// An axis-aligned bounding box in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The lower corner.
    pub min: Point3,
    /// The upper corner.
    pub max: Point3,
}

impl Aabb {
    /// A box from its two corners.
    pub fn new(min: Point3, max: Point3) -> Self {
        Self { min, max }
    }

    /// The tight box around `cuboid` at `pose`, grown by `margin` on every side.
    ///
    /// The world half extent along axis `i` is `sum_j |R_ij| h_j`, exact for a rotated box.
    pub fn from_cuboid(cuboid: &Cuboid, pose: &Pose, margin: Real) -> Self {
        let r = pose.rotation.to_rotation_matrix();
        let m = r.matrix().abs();
        let ext = m * cuboid.half_extents;
        let c = Point3::from(pose.translation.vector);
        let grow = ext.add_scalar(margin);
        Self {
            min: c - grow,
            max: c + grow,
        }
    }

    /// True when the boxes overlap or touch: closed intervals on all three axes
    /// (`a.min <= b.max && b.min <= a.max`), so exactly touching boxes form a pair.
    /// Inlined across crates: the broad phase calls it for every kept pair of every step.
    #[inline]
    pub fn intersects(&self, other: &Aabb) -> bool {
        (0..3).all(|i| self.min[i] <= other.max[i] && other.min[i] <= self.max[i])
    }

    /// The centre point.
    pub fn center(&self) -> Point3 {
        nalgebra::center(&self.min, &self.max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec3;
    use crate::test_support::{brick, turned_about_z};

    #[test]
    fn an_unrotated_box_has_its_half_extents_plus_the_margin() {
        let cuboid = brick();
        let pose = Pose::translation(10.0, -4.0, 0.5);
        let b = Aabb::from_cuboid(&cuboid, &pose, 0.25);
        assert_eq!(b.min, Point3::new(8.75, -6.25, -2.75));
        assert_eq!(b.max, Point3::new(11.25, -1.75, 3.75));
        assert_eq!(b.center(), Point3::new(10.0, -4.0, 0.5));
    }

    #[test]
    fn a_rotated_box_is_bounded_by_the_sum_of_its_projected_half_extents() {
        // 45 degrees about z: the x and y extents are both (1 + 2) / sqrt(2) = 2.1213.
        let cuboid = brick();
        let pose = turned_about_z(1.0, 0.0, 0.0, std::f32::consts::FRAC_PI_4);
        let b = Aabb::from_cuboid(&cuboid, &pose, 0.0);
        let e = 3.0 / std::f32::consts::SQRT_2;
        let close = |a: Real, b: Real| (a - b).abs() < 1e-5;
        assert!(close(b.min.x, 1.0 - e) && close(b.max.x, 1.0 + e), "{b:?}");
        assert!(close(b.min.y, -e) && close(b.max.y, e), "{b:?}");
        assert!(close(b.min.z, -3.0) && close(b.max.z, 3.0), "{b:?}");
        // Every corner of the box lies inside it.
        for v in cuboid.vertices() {
            let p = pose * v;
            assert!((0..3).all(|k| b.min[k] - 1e-5 <= p[k] && p[k] <= b.max[k] + 1e-5));
        }
    }

    #[test]
    fn boxes_intersect_when_their_closed_intervals_overlap_on_all_axes() {
        let unit = Aabb::new(Point3::origin(), Point3::new(1.0, 1.0, 1.0));
        assert!(unit.intersects(&unit));
        for axis in 0..3 {
            let shifted = |d: Real| {
                let mut off = Vec3::zeros();
                off[axis] = d;
                Aabb::new(unit.min + off, unit.max + off)
            };
            // Touching on either side counts (closed intervals), in both argument orders.
            for d in [1.0, -1.0] {
                assert!(unit.intersects(&shifted(d)), "touching at {d} on {axis}");
                assert!(shifted(d).intersects(&unit), "touching at {d} on {axis}");
            }
            for d in [1.001, -1.001] {
                assert!(!unit.intersects(&shifted(d)), "apart at {d} on {axis}");
                assert!(!shifted(d).intersects(&unit), "apart at {d} on {axis}");
            }
            assert!(unit.intersects(&shifted(0.5)));
        }
        // Apart on one axis only is enough to miss.
        let apart_z = Aabb::new(Point3::new(0.5, 0.5, 2.0), Point3::new(1.5, 1.5, 3.0));
        assert!(!unit.intersects(&apart_z) && !apart_z.intersects(&unit));
    }
}
