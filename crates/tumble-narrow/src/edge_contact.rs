//! Edge-edge contacts: one point, midway between the closest points of the two support edges.

use crate::BoxPair;
use tumble_geometry::{
    Point3, Real, SegmentClosestPoints, Vec3, closest_points_segments, nalgebra,
};

/// An edge-edge contact in A's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeContact {
    /// Edge of A (0..12, indexed as in `CUBOID_EDGES`).
    pub edge_a: usize,
    /// Edge of B.
    pub edge_b: usize,
    /// Closest points of the two edges, in A's frame.
    pub closest: SegmentClosestPoints,
    /// Overlap along the axis: positive when the edges pass through each other.
    pub depth: Real,
}

impl EdgeContact {
    /// Midpoint of the closest pair, in A's frame.
    pub fn midpoint(&self) -> Point3 {
        nalgebra::center(&self.closest.point_a, &self.closest.point_b)
    }
}

/// The edge along `axis` of `cuboid` farthest along local direction `dir`: `4 * axis + bit(lo) +
/// 2 * bit(hi)`, where `lo < hi` are the two other axes and a bit is set when `dir` is not
/// negative on that axis (the `CUBOID_EDGES` numbering).
pub fn support_edge(axis: usize, dir: &Vec3) -> usize {
    let lo = ((axis + 1) % 3).min((axis + 2) % 3);
    let hi = ((axis + 1) % 3).max((axis + 2) % 3);
    4 * axis + usize::from(dir[lo] >= 0.0) + 2 * usize::from(dir[hi] >= 0.0)
}

/// The contact between A's edges along axis `i` and B's along axis `j`, for the edge axis `normal`
/// (A's frame, from A to B): A's support edge along `normal`, B's along `-normal`.
pub fn edge_contact(pair: &BoxPair, i: usize, j: usize, normal: &Vec3) -> EdgeContact {
    let edge_a = support_edge(i, normal);
    let edge_b = support_edge(j, &-pair.rot.tr_mul(normal));
    let (a0, a1) = pair.a.edge(edge_a);
    let (b0, b1) = pair.b.edge(edge_b);
    let closest = closest_points_segments(&a0, &a1, &pair.b_to_a(&b0), &pair.b_to_a(&b1));
    EdgeContact {
        edge_a,
        edge_b,
        depth: (closest.point_a - closest.point_b).dot(normal),
        closest,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tests::{crossed_edges, cube};
    use tumble_geometry::{CUBOID_EDGES, Cuboid};

    #[test]
    fn support_edges_follow_the_cuboid_edge_numbering() {
        let cube = Cuboid::new(Vec3::repeat(1.0));
        for axis in 0..3 {
            for signs in 0..8usize {
                let dir = Vec3::from_fn(|k, _| if signs & (1 << k) != 0 { 1.0 } else { -1.0 });
                let e = support_edge(axis, &dir);
                // The support edge runs along `axis` and both its ends are support points of
                // `dir` among the vertices differing only along `axis`.
                assert_eq!(e / 4, axis);
                let [v0, v1] = CUBOID_EDGES[e];
                for v in [v0, v1] {
                    let p = cube.vertex(v);
                    for k in (0..3).filter(|&k| k != axis) {
                        assert_eq!(p[k], dir[k]);
                    }
                }
            }
        }
    }

    #[test]
    fn crossed_edges_meet_at_their_middles_with_the_overlap_as_depth() {
        let a = cube(1.0);
        // A turned 45 degrees about z (top edge along z at y = sqrt 2), B turned about x (bottom
        // edge along x at y = centre - sqrt 2), sunk 0.05 into A.
        let (pose_a, pose_b) = crossed_edges(1.0, -0.05);
        let pair = BoxPair::new(&a, &pose_a, &a, &pose_b);
        let normal_world = Vec3::y();
        let normal = pose_a.rotation.inverse_transform_vector(&normal_world);
        // A's local axes: x and y are turned in the world xy plane, z is the world z.
        let c = edge_contact(&pair, 2, 0, &normal);
        assert!((c.depth - 0.05).abs() < 1e-5, "depth {}", c.depth);
        let mid_world = pose_a * c.midpoint();
        assert!(mid_world.x.abs() < 1e-5 && mid_world.z.abs() < 1e-5);
        assert!((mid_world.y - (2f32.sqrt() - 0.025)).abs() < 1e-5);
    }
}
