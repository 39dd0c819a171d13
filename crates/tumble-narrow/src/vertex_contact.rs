//! The closest vertex pair of two separated boxes: the contact when the SAT axis is not the
//! closest pair's direction.
//!
//! When the boxes are apart, the closest pair is either a point of a face over which the other box
//! lies (found by the face contact), an interior point of each of two crossing edges (found by the
//! edge contact on an SAT axis), or it involves a vertex of one box and any feature of the other.
//! The last case, a vertex against an edge or a vertex, has a direction that is no SAT axis: it is
//! found here by measuring every vertex against the other box.

use crate::BoxPair;
use tumble_geometry::{Point3, Real, Vec3};

/// A vertex of one box and the nearest point of the other, both in A's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexContact {
    /// The point on A.
    pub point_a: Point3,
    /// The point on B.
    pub point_b: Point3,
    /// From the point on A to the point on B, computed as a difference where both are known
    /// at the scale of the gap (so `point_b - point_a` may differ from it in the low digits when
    /// the boxes are much larger than the gap): the contact normal's direction.
    pub gap: Vec3,
    /// Their distance (0 when the vertex is inside the other box).
    pub distance: Real,
    /// The vertex index (0..8).
    pub vertex: usize,
    /// True when the vertex is A's, false when it is B's.
    pub on_a: bool,
}

/// The vertex of either box nearest to the other box: 16 clamps, no branch on the geometry.
pub fn closest_vertex(pair: &BoxPair) -> VertexContact {
    let mut best = VertexContact {
        point_a: Point3::origin(),
        point_b: Point3::origin(),
        gap: Vec3::zeros(),
        distance: Real::INFINITY,
        vertex: 0,
        on_a: false,
    };
    for v in 0..8 {
        // B's vertex against A, in A's frame.
        let vb = pair.b_to_a(&pair.b.vertex(v));
        let on_a = pair.a.local_closest_point(&vb);
        let gap = vb - on_a;
        let d = gap.norm();
        if d < best.distance {
            best = VertexContact {
                point_a: on_a,
                point_b: vb,
                gap,
                distance: d,
                vertex: v,
                on_a: false,
            };
        }
        // A's vertex against B, in B's frame; the gap vector is rotated back to A's frame rather
        // than the point, so that it keeps the digits of a gap much shorter than the boxes.
        let va = pair.a.vertex(v);
        let va_in_b = pair.a_to_b(&va);
        let on_b = pair.b.local_closest_point(&va_in_b);
        let gap = pair.rot * (on_b - va_in_b);
        let d = gap.norm();
        if d < best.distance {
            best = VertexContact {
                point_a: va,
                point_b: va + gap,
                gap,
                distance: d,
                vertex: v,
                on_a: true,
            };
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_geometry::{Cuboid, Pose, Vec3};

    #[test]
    fn diagonal_corners_measure_the_euclidean_gap() {
        // Unit cubes offset by (2.3, 2.4, 0): the corner region, gap vector (0.3, 0.4, 0), 0.5 long,
        // while every SAT axis sees at most 0.4.
        let cube = Cuboid::new(Vec3::repeat(1.0));
        let pair = BoxPair::new(
            &cube,
            &Pose::identity(),
            &cube,
            &Pose::translation(2.3, 2.4, 0.0),
        );
        let c = closest_vertex(&pair);
        assert!((c.distance - 0.5).abs() < 1e-6);
        assert!((c.point_b - c.point_a - Vec3::new(0.3, 0.4, 0.0)).norm() < 1e-6);
    }
}
