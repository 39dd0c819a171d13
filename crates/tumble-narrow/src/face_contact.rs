//! Face contacts: clip the incident face against the reference face's side planes.
//!
//! Everything happens in the reference box's frame, where the reference face is `x_i = +-h_i` and
//! its four side planes are `x_j = +-h_j`, so every signed distance is one subtraction.

use crate::BoxPair;
use crate::feature_id::{SIDE_LABEL_BASE, face_point_id};
use tumble_geometry::{
    CUBOID_FACES, ClipPolygon, ContactPoint, MAX_CLIP_VERTICES, Plane, Point3, Real, Vec3,
};

/// Contact points before reduction, in the reference box's frame.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FaceContact {
    /// Outward unit normal of the reference face.
    pub normal: Vec3,
    /// The incident face (of the other box).
    pub incident_face: usize,
    /// The clipped points within the margin: midpoints between the surfaces, depth, id.
    pub points: [ContactPoint; MAX_CLIP_VERTICES],
    /// Number of valid points.
    pub len: usize,
    /// Smallest separation over the whole clipped polygon, margin or not (`+inf` when it is
    /// empty): each of its points lies over the reference face, so this is a true distance
    /// between two surface points when positive.
    pub min_separation: Real,
}

impl FaceContact {
    /// The valid points.
    pub fn points(&self) -> &[ContactPoint] {
        &self.points[..self.len]
    }
}

/// Clips the incident face of `pair.b` against face `reference` of `pair.a` (the reference box is
/// `pair.a`; pass a swapped pair for B's faces) and keeps the points deeper than `-margin`.
/// `kind` is the id kind code (face of A or of B).
pub fn face_contact(pair: &BoxPair, reference: usize, margin: Real, kind: u32) -> FaceContact {
    let axis = reference / 2;
    let sign = if reference.is_multiple_of(2) {
        1.0
    } else {
        -1.0
    };
    let normal = Vec3::ith(axis, sign);
    let height = pair.a.half_extents[axis];

    // The incident face: the face of the other box most anti-parallel to the reference normal.
    let normal_in_b = pair.rot.tr_mul(&normal);
    let incident_face = pair.b.best_face(&-normal_in_b);
    let corners: [Point3; 4] = CUBOID_FACES[incident_face].map(|v| pair.b_to_a(&pair.b.vertex(v)));
    let mut polygon = ClipPolygon::from_corners(&corners, &[0, 1, 2, 3]);

    // The four side planes, two per axis across the normal.
    for (slot, side_axis) in (0..3u32).zip((0..3).filter(|&k| k != axis)) {
        for (negative, side_sign) in [(0, 1.0), (1, -1.0)] {
            let plane = Plane {
                normal: Vec3::ith(side_axis, side_sign),
                offset: pair.a.half_extents[side_axis],
            };
            polygon = polygon.clip(&plane, SIDE_LABEL_BASE + 2 * slot + negative);
        }
    }

    let mut contact = FaceContact {
        normal,
        incident_face,
        min_separation: Real::INFINITY,
        ..Default::default()
    };
    for v in polygon.vertices() {
        let depth = height - normal.dot(&v.position.coords);
        contact.min_separation = contact.min_separation.min(-depth);
        if depth >= -margin && contact.len < MAX_CLIP_VERTICES {
            contact.points[contact.len] = ContactPoint {
                // Midway between the incident point and its projection on the reference face.
                position: v.position + normal * (0.5 * depth),
                depth,
                id: face_point_id(
                    kind,
                    reference as u32,
                    incident_face as u32,
                    v.edge_in,
                    v.edge_out,
                ),
            };
            contact.len += 1;
        }
    }
    contact
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feature_id::KIND_FACE_A;
    use crate::tests::cube;
    use tumble_geometry::{Cuboid, Pose, Rot, nalgebra::Translation3};

    #[test]
    fn a_small_box_sunk_into_a_large_one_gives_its_four_bottom_corners() {
        let big = Cuboid::new(Vec3::new(5.0, 1.0, 5.0));
        let small = cube(0.5);
        // Small box's bottom at y = 0.9: 0.1 below the big box's top face (y = 1).
        let pair = BoxPair::new(
            &big,
            &Pose::identity(),
            &small,
            &Pose::translation(1.0, 1.4, -2.0),
        );
        let c = face_contact(&pair, 2, 0.0, KIND_FACE_A);
        assert_eq!(c.incident_face, 3, "the small box's -y face is incident");
        assert_eq!(c.len, 4);
        for p in c.points() {
            // Depth 0.1 and midpoint at y = 0.95, up to f32 rounding of 1.4 - 0.5.
            assert!((p.depth - 0.1).abs() < 1e-6);
            assert!((p.position.y - 0.95).abs() < 1e-6);
            assert!(
                (p.position.x - 1.0).abs() <= 0.5 + 1e-6
                    && (p.position.z + 2.0).abs() <= 0.5 + 1e-6
            );
        }
        assert!((c.min_separation + 0.1).abs() < 1e-6);
    }

    #[test]
    fn an_overhanging_box_is_cut_at_the_reference_face_edge() {
        let a = cube(1.0);
        // B overhangs A's +x side by 0.5: the clipped patch spans x in [0, 1], area 1 x 1.
        let pair = BoxPair::new(
            &a,
            &Pose::identity(),
            &Cuboid::new(Vec3::new(0.75, 0.5, 0.5)),
            &Pose::translation(0.75, 1.45, 0.0),
        );
        let c = face_contact(&pair, 2, 0.0, KIND_FACE_A);
        assert_eq!(c.len, 4);
        let xs: Vec<Real> = c.points().iter().map(|p| p.position.x).collect();
        assert!(xs.iter().all(|&x| (0.0 - 1e-6..=1.0 + 1e-6).contains(&x)));
        // Two points are on the side plane x = 1, made by B's edges crossing it: (edge, side) labels.
        let cut: Vec<_> = c
            .points()
            .iter()
            .filter(|p| (p.position.x - 1.0).abs() < 1e-6)
            .collect();
        assert_eq!(cut.len(), 2);
        assert_ne!(cut[0].id, cut[1].id);
    }

    #[test]
    fn points_above_the_margin_are_dropped_but_still_measured() {
        let a = cube(1.0);
        // B tilted 0.2 rad about z and resting with its lowest corner 0.01 into A.
        let tilt = Rot::from_euler_angles(0.0, 0.0, 0.2);
        let b = cube(0.5);
        let lowest = (tilt * Vec3::new(-0.5, -0.5, 0.0))
            .y
            .min((tilt * Vec3::new(0.5, -0.5, 0.0)).y);
        let pose_b = Pose::from_parts(Translation3::new(0.0, 1.0 - 0.01 - lowest, 0.0), tilt);
        let pair = BoxPair::new(&a, &Pose::identity(), &b, &pose_b);
        let tight = face_contact(&pair, 2, 0.0, KIND_FACE_A);
        // Only the two corners of the low edge are below the face; the high edge is sin(0.2)
        // (about 0.2) above it.
        assert_eq!(tight.len, 2);
        assert!((tight.min_separation + 0.01).abs() < 1e-5);
        let wide = face_contact(&pair, 2, 0.5, KIND_FACE_A);
        assert_eq!(wide.len, 4);
    }
}
