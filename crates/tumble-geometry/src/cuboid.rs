//! The cuboid collider: vertices, faces with outward normals, edges, support points.
//!
//! Indexing conventions (shared with the WGSL kernels):
//! - vertex `v` (0..8) has coordinate `+h` on axis `k` when bit `k` of `v` is set, else `-h`;
//! - face `f` (0..6) has outward normal along axis `f / 2`, positive when `f` is even;
//! - edge `e` (0..12) runs along axis `e / 4`.

use crate::{Aabb, Point3, Pose, Real, Vec3};

/// A box centred on its local origin, given by its half extents (all positive).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Cuboid {
    /// Half the box's size along each local axis.
    pub half_extents: Vec3,
}

/// One face of a cuboid, in the cuboid's local frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CuboidFace {
    /// Outward unit normal.
    pub normal: Vec3,
    /// The four corner vertex indices, counter-clockwise seen from outside.
    pub vertices: [usize; 4],
}

/// The six faces: `+x, -x, +y, -y, +z, -z`, corners counter-clockwise seen from outside.
pub const CUBOID_FACES: [[usize; 4]; 6] = [
    [1, 3, 7, 5], // +x
    [0, 4, 6, 2], // -x
    [2, 6, 7, 3], // +y
    [0, 1, 5, 4], // -y
    [4, 5, 7, 6], // +z
    [0, 2, 3, 1], // -z
];

/// The twelve edges as vertex index pairs, four along x, then four along y, then four along z.
pub const CUBOID_EDGES: [[usize; 2]; 12] = [
    [0, 1],
    [2, 3],
    [4, 5],
    [6, 7], // along x
    [0, 2],
    [1, 3],
    [4, 6],
    [5, 7], // along y
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7], // along z
];

impl Cuboid {
    /// A cuboid from its half extents.
    pub fn new(half_extents: Vec3) -> Self {
        Self { half_extents }
    }

    /// Local vertex `v` (0..8): bit `k` of `v` selects the sign on axis `k`.
    pub fn vertex(&self, v: usize) -> Point3 {
        let h = self.half_extents;
        let s = |k: usize| if v & (1 << k) != 0 { 1.0 } else { -1.0 };
        Point3::new(s(0) * h.x, s(1) * h.y, s(2) * h.z)
    }

    /// The eight local vertices, indexed as in the module docs.
    pub fn vertices(&self) -> [Point3; 8] {
        std::array::from_fn(|v| self.vertex(v))
    }

    /// Local face `f` (0..6) with its outward normal and corners.
    pub fn face(&self, f: usize) -> CuboidFace {
        let mut normal = Vec3::zeros();
        normal[f / 2] = if f.is_multiple_of(2) { 1.0 } else { -1.0 };
        CuboidFace {
            normal,
            vertices: CUBOID_FACES[f],
        }
    }

    /// The four local corners of face `f`, counter-clockwise seen from outside.
    pub fn face_polygon(&self, f: usize) -> [Point3; 4] {
        CUBOID_FACES[f].map(|v| self.vertex(v))
    }

    /// Local edge `e` (0..12) as its two end points.
    pub fn edge(&self, e: usize) -> (Point3, Point3) {
        let [a, b] = CUBOID_EDGES[e];
        (self.vertex(a), self.vertex(b))
    }

    /// The local vertex farthest along local direction `dir` (ties go to the positive side).
    pub fn local_support(&self, dir: &Vec3) -> Point3 {
        let h = self.half_extents;
        Point3::new(
            h.x.copysign(if dir.x == 0.0 { 1.0 } else { dir.x }),
            h.y.copysign(if dir.y == 0.0 { 1.0 } else { dir.y }),
            h.z.copysign(if dir.z == 0.0 { 1.0 } else { dir.z }),
        )
    }

    /// The world-space vertex farthest along world direction `dir`, for the cuboid at `pose`.
    pub fn support(&self, pose: &Pose, dir: &Vec3) -> Point3 {
        let local_dir = pose.rotation.inverse_transform_vector(dir);
        pose * self.local_support(&local_dir)
    }

    /// The local face whose outward normal is most aligned with local direction `dir`.
    pub fn best_face(&self, dir: &Vec3) -> usize {
        let a = dir.abs();
        let axis = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        2 * axis + usize::from(dir[axis] < 0.0)
    }

    /// The point of the solid box nearest to local point `p` (`p` itself when inside).
    ///
    /// Written with `max`/`min` rather than `clamp`, which panics on inverted bounds.
    pub fn local_closest_point(&self, p: &Point3) -> Point3 {
        let h = self.half_extents;
        Point3::new(
            p.x.max(-h.x).min(h.x),
            p.y.max(-h.y).min(h.y),
            p.z.max(-h.z).min(h.z),
        )
    }

    /// Volume of the box.
    pub fn volume(&self) -> Real {
        8.0 * self.half_extents.x * self.half_extents.y * self.half_extents.z
    }

    /// The world AABB of this cuboid at `pose`, grown by `margin`.
    pub fn aabb(&self, pose: &Pose, margin: Real) -> Aabb {
        Aabb::from_cuboid(self, pose, margin)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{brick, turned_about_z};

    #[test]
    fn vertex_bits_select_the_sign_of_each_axis() {
        let c = brick();
        assert_eq!(c.vertex(0), Point3::new(-1.0, -2.0, -3.0));
        assert_eq!(c.vertex(1), Point3::new(1.0, -2.0, -3.0));
        assert_eq!(c.vertex(2), Point3::new(-1.0, 2.0, -3.0));
        assert_eq!(c.vertex(4), Point3::new(-1.0, -2.0, 3.0));
        assert_eq!(c.vertex(7), Point3::new(1.0, 2.0, 3.0));
        assert_eq!(c.vertices()[6], c.vertex(6));
    }

    #[test]
    fn faces_point_outward_and_wind_counter_clockwise_from_outside() {
        let c = brick();
        for f in 0..6 {
            let face = c.face(f);
            let mut n = Vec3::zeros();
            n[f / 2] = if f % 2 == 0 { 1.0 } else { -1.0 };
            assert_eq!(face.normal, n, "face {f}");
            let p = c.face_polygon(f);
            // All four corners lie on the face's plane, at h along the normal.
            for q in &p {
                assert_eq!(q.coords.dot(&n), c.half_extents[f / 2], "face {f}");
            }
            // Counter-clockwise seen from outside: consecutive edges turn about +normal.
            for k in 0..4 {
                let e1 = p[(k + 1) % 4] - p[k];
                let e2 = p[(k + 2) % 4] - p[(k + 1) % 4];
                assert!(e1.cross(&e2).dot(&n) > 0.0, "face {f} corner {k}");
            }
        }
    }

    #[test]
    fn edges_run_along_their_axis_between_neighbour_vertices() {
        let c = brick();
        for e in 0..12 {
            let (a, b) = c.edge(e);
            let d = b - a;
            let axis = e / 4;
            assert_eq!(d[axis], 2.0 * c.half_extents[axis], "edge {e}");
            assert_eq!(d.norm(), 2.0 * c.half_extents[axis], "edge {e}");
        }
    }

    #[test]
    fn support_is_the_farthest_corner_along_the_direction() {
        let c = brick();
        for (dir, corner) in [
            (Vec3::new(1.0, -1.0, 0.5), Point3::new(1.0, -2.0, 3.0)),
            (Vec3::new(-0.1, 2.0, -9.0), Point3::new(-1.0, 2.0, -3.0)),
        ] {
            assert_eq!(c.local_support(&dir), corner, "along {dir}");
        }
        // Zero components go to the positive side.
        assert_eq!(c.local_support(&Vec3::zeros()), Point3::new(1.0, 2.0, 3.0));
        // In the world: a quarter turn about z maps local +x to world +y.
        let pose = turned_about_z(5.0, 0.0, 0.0, std::f32::consts::FRAC_PI_2);
        let s = c.support(&pose, &Vec3::new(0.0, 1.0, 0.0));
        // Farthest along world +y is local +x at h.x = 1 from the centre.
        assert!((s.y - 1.0).abs() < 1e-5, "{s}");
        for v in c.vertices() {
            assert!((pose * v).y <= s.y + 1e-5);
        }
    }

    #[test]
    fn best_face_is_the_most_aligned_outward_normal() {
        let c = brick();
        assert_eq!(c.best_face(&Vec3::new(1.0, 0.5, 0.5)), 0);
        assert_eq!(c.best_face(&Vec3::new(-1.0, 0.5, 0.5)), 1);
        assert_eq!(c.best_face(&Vec3::new(0.1, 0.9, -0.5)), 2);
        assert_eq!(c.best_face(&Vec3::new(0.1, -0.9, -0.5)), 3);
        assert_eq!(c.best_face(&Vec3::new(0.1, 0.2, 0.3)), 4);
        assert_eq!(c.best_face(&Vec3::new(0.1, 0.2, -0.3)), 5);
        // Ties go to the lower axis.
        assert_eq!(c.best_face(&Vec3::new(1.0, 1.0, 1.0)), 0);
        assert_eq!(c.best_face(&Vec3::new(0.0, -1.0, 1.0)), 3);
        // No direction at all: the positive face, as `local_support` breaks zeros.
        assert_eq!(c.best_face(&Vec3::zeros()), 0);
    }

    #[test]
    fn closest_point_clamps_outside_points_and_keeps_inside_ones() {
        let c = brick();
        let inside = Point3::new(0.5, -1.0, 2.0);
        for (p, nearest) in [
            (inside, inside),
            (Point3::new(3.0, -5.0, 0.0), Point3::new(1.0, -2.0, 0.0)),
            (Point3::new(-3.0, 5.0, -7.0), Point3::new(-1.0, 2.0, -3.0)),
        ] {
            assert_eq!(c.local_closest_point(&p), nearest, "from {p}");
        }
    }

    #[test]
    fn volume_and_aabb_follow_the_half_extents() {
        let c = brick();
        assert_eq!(c.volume(), 48.0);
        let b = c.aabb(&Pose::translation(1.0, 1.0, 1.0), 0.5);
        assert_eq!(b.min, Point3::new(-0.5, -1.5, -2.5));
        assert_eq!(b.max, Point3::new(2.5, 3.5, 4.5));
    }
}
