//! The cuboid collider: vertices, faces with outward normals, edges, support points.
//!
//! Indexing conventions (shared with the WGSL kernels):
//! - vertex `v` (0..8) has coordinate `+h` on axis `k` when bit `k` of `v` is set, else `-h`;
//! - face `f` (0..6) has outward normal along axis `f / 2`, positive when `f` is even;
//! - edge `e` (0..12) runs along axis `e / 4`.

use crate::{Aabb, Point3, Pose, Real, Vec3};

/// A box centred on its local origin, given by its half extents (all positive).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
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
