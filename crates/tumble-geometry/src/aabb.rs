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
    pub fn intersects(&self, other: &Aabb) -> bool {
        (0..3).all(|i| self.min[i] <= other.max[i] && other.min[i] <= self.max[i])
    }

    /// The centre point.
    pub fn center(&self) -> Point3 {
        nalgebra::center(&self.min, &self.max)
    }
}
