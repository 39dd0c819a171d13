//! Ray casts against boxes (axis-aligned and oriented) and point queries on oriented boxes.
//!
//! Method: the slab test. In the box's frame the solid box is the intersection of three slabs
//! `|x_k| <= h_k`; a ray `o + t d` is inside slab `k` for `t` between `(-h_k - o_k) / d_k` and
//! `(h_k - o_k) / d_k`, and inside the box where all three intervals and `[0, max_toi]`
//! overlap. The hit is the start of that overlap, and its normal the outward normal of the
//! slab whose interval started last. This is exact up to `f32` rounding: one subtraction and
//! one division per slab after the change of frame, so the time of impact is off by a few ulps
//! of the coordinates involved divided by the speed along the entry axis.
//!
//! Boxes are solid: a ray starting inside (or on the surface of) a box hits it at `toi = 0`,
//! with a zero normal, as no surface was crossed (parry's `solid = true` convention).

use crate::{Aabb, Cuboid, Point3, Pose, Real, Vec3};

/// Where a ray or a swept box first touches a box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CastHit {
    /// The time of impact, in units of the cast's direction (or velocity): the ray touches the
    /// box at `origin + toi * dir`. 0 when the cast starts inside (or touching) the box.
    pub toi: Real,
    /// The box's outward unit normal where it is touched, world frame; zero when `toi` is 0
    /// because the cast started inside or touching (no surface was crossed).
    pub normal: Vec3,
}

impl CastHit {
    /// The hit of a cast that starts inside or touching the box: time 0, no normal.
    pub fn at_start() -> Self {
        CastHit {
            toi: 0.0,
            normal: Vec3::zeros(),
        }
    }
}

/// The nearest point of a box to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointProjection {
    /// The nearest point of the box (world frame): the query point itself when it is inside
    /// and the projection is solid, else a point on the surface.
    pub point: Point3,
    /// True when the query point is inside the closed box (on the surface counts).
    pub is_inside: bool,
}

/// The slab test in a frame where the box is `[min, max]`: the parameter interval where
/// `o + t d` is inside the box, clipped to `[0, max_toi]`, with the axis and the sign of the
/// outward normal of the slab that was entered last (`None` when the start point is inside).
fn slab_test(
    o: &Vec3,
    d: &Vec3,
    min: &Vec3,
    max: &Vec3,
    max_toi: Real,
) -> Option<(Real, Option<(usize, Real)>)> {
    if max_toi.is_nan() || max_toi < 0.0 {
        return None;
    }
    let (mut enter, mut exit) = (0.0, max_toi);
    let mut entered = None;
    for k in 0..3 {
        if d[k] == 0.0 {
            // Parallel to the slab: inside it for every t, or never (a NaN is never inside).
            let inside = min[k] <= o[k] && o[k] <= max[k];
            if !inside {
                return None;
            }
            continue;
        }
        // Division rather than multiplication by a reciprocal: a zero numerator stays 0
        // (never 0 * inf = NaN), and a tiny d overflows to an infinite time, which is right.
        let t_min = (min[k] - o[k]) / d[k];
        let t_max = (max[k] - o[k]) / d[k];
        if t_min.is_nan() || t_max.is_nan() {
            return None;
        }
        let (near, far, sign) = if t_min <= t_max {
            (t_min, t_max, -1.0)
        } else {
            (t_max, t_min, 1.0)
        };
        if near > enter {
            enter = near;
            entered = Some((k, sign));
        }
        if far < exit {
            exit = far;
        }
        // Both are numbers here (NaN times returned above).
        if enter > exit {
            return None;
        }
    }
    Some((enter, entered))
}

impl Aabb {
    /// The time of impact of the ray `origin + t dir`, `t` in `[0, max_toi]`, with this box
    /// (solid: 0 when `origin` is inside). `None` on a miss. The slab test of the module docs.
    pub fn cast_ray(&self, origin: &Point3, dir: &Vec3, max_toi: Real) -> Option<Real> {
        slab_test(
            &origin.coords,
            dir,
            &self.min.coords,
            &self.max.coords,
            max_toi,
        )
        .map(|(t, _)| t)
    }

    /// True when `point` is inside the closed box.
    pub fn contains_point(&self, point: &Point3) -> bool {
        (0..3).all(|k| self.min[k] <= point[k] && point[k] <= self.max[k])
    }

    /// The smallest box holding both boxes.
    pub fn merged(&self, other: &Aabb) -> Aabb {
        Aabb::new(self.min.inf(&other.min), self.max.sup(&other.max))
    }

    /// The box grown by `extent[k]` on both sides along each axis `k`.
    pub fn grown(&self, extent: &Vec3) -> Aabb {
        Aabb::new(self.min - extent, self.max + extent)
    }

    /// The half extents (half the size along each axis).
    pub fn half_extents(&self) -> Vec3 {
        (self.max - self.min) * 0.5
    }

    /// The squared distance from `point` to the closed box (0 inside).
    pub fn distance_squared_to_point(&self, point: &Point3) -> Real {
        let below = self.min - point;
        let above = point - self.max;
        below.sup(&above).sup(&Vec3::zeros()).norm_squared()
    }
}

impl Cuboid {
    /// The first hit of the ray `origin + t dir`, `t` in `[0, max_toi]`, with this box at
    /// `pose` (solid: `toi = 0` and a zero normal when `origin` is inside or on the surface).
    /// `dir` need not be unit length; `toi` is in its units. `None` on a miss, for a negative
    /// `max_toi`, and for a NaN
    /// anywhere in the input. The slab test of the module docs, in the box's frame.
    pub fn cast_ray(
        &self,
        pose: &Pose,
        origin: &Point3,
        dir: &Vec3,
        max_toi: Real,
    ) -> Option<CastHit> {
        let o = pose.inverse_transform_point(origin).coords;
        let d = pose.rotation.inverse_transform_vector(dir);
        let h = self.half_extents;
        let (toi, entered) = slab_test(&o, &d, &-h, &h, max_toi)?;
        let normal = match entered {
            Some((k, sign)) => pose.rotation * Vec3::ith(k, sign),
            None => Vec3::zeros(),
        };
        Some(CastHit { toi, normal })
    }

    /// True when world point `point` is inside the closed box at `pose`.
    pub fn contains_point(&self, pose: &Pose, point: &Point3) -> bool {
        let p = pose.inverse_transform_point(point);
        (0..3).all(|k| p[k].abs() <= self.half_extents[k])
    }

    /// The point of the box at `pose` nearest to world point `point`. With `solid`, a point
    /// inside is its own projection; without, it goes to the nearest face (the face whose plane
    /// is closest; ties go to the lower axis). Exact up to rounding: a clamp in the box's frame.
    pub fn project_point(&self, pose: &Pose, point: &Point3, solid: bool) -> PointProjection {
        let p = pose.inverse_transform_point(point);
        let h = self.half_extents;
        let is_inside = (0..3).all(|k| p[k].abs() <= h[k]);
        let local = if !is_inside {
            self.local_closest_point(&p)
        } else if solid {
            p
        } else {
            // The face with the least depth below it.
            let depth = h - p.coords.abs();
            let k = if depth.x <= depth.y && depth.x <= depth.z {
                0
            } else if depth.y <= depth.z {
                1
            } else {
                2
            };
            let mut q = p;
            q[k] = h[k].copysign(p[k]);
            q
        };
        PointProjection {
            point: pose * local,
            is_inside,
        }
    }

    /// The distance from world point `point` to the solid box at `pose` (0 inside).
    pub fn distance_to_point(&self, pose: &Pose, point: &Point3) -> Real {
        let p = pose.inverse_transform_point(point);
        (p - self.local_closest_point(&p)).norm()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{brick, turned_about_z};

    #[test]
    fn a_ray_along_an_axis_hits_the_facing_face() {
        let c = brick();
        let pose = Pose::translation(10.0, 0.0, 0.0);
        let hit = c
            .cast_ray(&pose, &Point3::origin(), &Vec3::x(), 100.0)
            .expect("hit");
        assert_eq!(hit.toi, 9.0);
        assert_eq!(hit.normal, -Vec3::x());
        // Twice the speed, half the time.
        let hit = c
            .cast_ray(&pose, &Point3::origin(), &(2.0 * Vec3::x()), 100.0)
            .expect("hit");
        assert_eq!(hit.toi, 4.5);
        // Too short, pointing away, or passing beside: no hit.
        assert!(
            c.cast_ray(&pose, &Point3::origin(), &Vec3::x(), 8.9)
                .is_none()
        );
        assert!(
            c.cast_ray(&pose, &Point3::origin(), &-Vec3::x(), 100.0)
                .is_none()
        );
        let beside = Point3::new(0.0, 2.5, 0.0);
        assert!(c.cast_ray(&pose, &beside, &Vec3::x(), 100.0).is_none());
    }

    #[test]
    fn a_rotated_box_is_hit_on_its_turned_face() {
        // A quarter turn about z: local +y points to world -x, so the face hit from the
        // origin is local +y at 2 m from the centre.
        let c = brick();
        let pose = turned_about_z(10.0, 0.0, 0.0, std::f32::consts::FRAC_PI_2);
        let hit = c
            .cast_ray(&pose, &Point3::origin(), &Vec3::x(), 100.0)
            .expect("hit");
        assert!((hit.toi - 8.0).abs() < 1e-5, "{hit:?}");
        assert!((hit.normal + Vec3::x()).norm() < 1e-6, "{hit:?}");
    }

    #[test]
    fn a_ray_from_inside_hits_at_zero_with_no_normal() {
        let c = brick();
        let hit = c
            .cast_ray(
                &Pose::identity(),
                &Point3::new(0.5, 0.0, 0.0),
                &Vec3::y(),
                1.0,
            )
            .expect("inside");
        assert_eq!(hit, CastHit::at_start());
    }

    #[test]
    fn nan_input_misses_rather_than_hits() {
        let c = brick();
        let nan = Vec3::new(Real::NAN, 0.0, 0.0);
        assert!(
            c.cast_ray(&Pose::identity(), &Point3::new(5.0, 0.0, 0.0), &nan, 10.0)
                .is_none()
        );
        let origin = Point3::new(Real::NAN, 0.0, 0.0);
        assert!(
            c.cast_ray(&Pose::identity(), &origin, &Vec3::y(), 10.0)
                .is_none()
        );
    }

    #[test]
    fn aabb_ray_casts_clip_to_the_segment() {
        let b = Aabb::new(Point3::new(1.0, -1.0, -1.0), Point3::new(2.0, 1.0, 1.0));
        assert_eq!(b.cast_ray(&Point3::origin(), &Vec3::x(), 5.0), Some(1.0));
        assert_eq!(b.cast_ray(&Point3::origin(), &Vec3::x(), 0.5), None);
        assert_eq!(
            b.cast_ray(&Point3::new(1.5, 0.0, 0.0), &Vec3::x(), 0.5),
            Some(0.0)
        );
        assert!(b.contains_point(&Point3::new(2.0, 1.0, -1.0)));
        assert!(!b.contains_point(&Point3::new(2.01, 1.0, -1.0)));
        assert_eq!(
            b.distance_squared_to_point(&Point3::new(0.0, 2.0, 0.0)),
            2.0
        );
        let m = b.merged(&Aabb::new(Point3::origin(), Point3::new(0.5, 3.0, 0.0)));
        assert_eq!(m.min, Point3::new(0.0, -1.0, -1.0));
        assert_eq!(m.max, Point3::new(2.0, 3.0, 1.0));
        assert_eq!(
            b.grown(&Vec3::repeat(1.0)).half_extents(),
            Vec3::new(1.5, 2.0, 2.0)
        );
    }

    #[test]
    fn points_project_onto_the_nearest_part_of_the_box() {
        let c = brick();
        let pose = turned_about_z(0.0, 0.0, 5.0, std::f32::consts::FRAC_PI_2);
        // Local +x is world +y; 3 m above the centre in world y is 2 m outside that face.
        let p = Point3::new(0.0, 3.0, 5.0);
        assert!(!c.contains_point(&pose, &p));
        let proj = c.project_point(&pose, &p, true);
        assert!(!proj.is_inside);
        assert!(
            (proj.point - Point3::new(0.0, 1.0, 5.0)).norm() < 1e-5,
            "{proj:?}"
        );
        assert!((c.distance_to_point(&pose, &p) - 2.0).abs() < 1e-5);
        // Inside: solid keeps the point, hollow moves it to the nearest face (local +x again).
        let q = Point3::new(0.0, 0.8, 5.0);
        assert!(c.contains_point(&pose, &q));
        assert_eq!(c.project_point(&pose, &q, true).point, q);
        let hollow = c.project_point(&pose, &q, false);
        assert!(hollow.is_inside);
        assert!(
            (hollow.point - Point3::new(0.0, 1.0, 5.0)).norm() < 1e-5,
            "{hollow:?}"
        );
        assert_eq!(c.distance_to_point(&pose, &q), 0.0);
    }
}
