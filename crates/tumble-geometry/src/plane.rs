//! Planes and the signed distance of a point to a plane (the thesis's Algorithm 3).

use crate::{Point3, Real, Vec3};

/// A plane `normal . x = offset`, with a unit normal; its positive side is where the normal points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Unit normal, pointing to the positive ("outside") half-space.
    pub normal: Vec3,
    /// Signed distance of the plane from the origin along `normal`.
    pub offset: Real,
}

impl Plane {
    /// The plane through `point` with unit normal `normal`.
    pub fn from_point_normal(point: &Point3, normal: &Vec3) -> Self {
        Self {
            normal: *normal,
            offset: normal.dot(&point.coords),
        }
    }

    /// Signed distance of `point` to the plane: positive on the side the normal points to.
    pub fn signed_distance(&self, point: &Point3) -> Real {
        self.normal.dot(&point.coords) - self.offset
    }

    /// The foot of the perpendicular from `point` onto the plane.
    pub fn project(&self, point: &Point3) -> Point3 {
        point - self.normal * self.signed_distance(point)
    }
}

/// Signed distance of `point` to the plane through `plane_point` with unit normal `plane_normal`.
pub fn signed_distance_to_plane(point: &Point3, plane_point: &Point3, plane_normal: &Vec3) -> Real {
    plane_normal.dot(&(point - plane_point))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signed_distance_is_positive_on_the_normal_side_and_exact_for_axis_planes() {
        let plane = Plane::from_point_normal(&Point3::new(0.0, 2.0, 0.0), &Vec3::y());
        // Points straight above and below the plane: the distance is the height difference.
        assert_eq!(plane.signed_distance(&Point3::new(5.0, 3.5, -1.0)), 1.5);
        assert_eq!(plane.signed_distance(&Point3::new(0.0, 0.5, 0.0)), -1.5);
        assert_eq!(
            signed_distance_to_plane(
                &Point3::new(5.0, 3.5, -1.0),
                &Point3::new(0.0, 2.0, 0.0),
                &Vec3::y()
            ),
            1.5
        );
    }

    #[test]
    fn projection_lands_on_the_plane_along_the_normal() {
        let n = Vec3::new(1.0, 1.0, 1.0).normalize();
        let plane = Plane::from_point_normal(&Point3::new(1.0, 0.0, 0.0), &n);
        let p = Point3::new(3.0, -2.0, 4.0);
        let q = plane.project(&p);
        // The foot is on the plane (rounding of a few ulps of the coordinates) ...
        assert!(plane.signed_distance(&q).abs() < 1e-5);
        // ... and the move from p to its foot is along the normal only.
        assert!((p - q).cross(&n).norm() < 1e-5);
    }
}
