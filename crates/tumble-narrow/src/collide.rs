//! Box-box collision: the SAT axis, the contact built on it, and the reduction to four points.

use crate::BoxPair;
use crate::axis_choice::{deepest_axis, preferred_axis};
use crate::edge_contact::edge_contact;
use crate::face_contact::face_contact;
use crate::feature_id::{KIND_FACE_A, KIND_FACE_B, edge_point_id, vertex_point_id};
use crate::sat::{
    SatAxis, SatQuery, axis_separation, edge_axis, face_a_separation, face_b_separation,
};
use crate::tolerance::WITNESS_TOL;
use crate::vertex_contact::closest_vertex;
use tumble_geometry::{
    ContactPoint, Cuboid, FeatureKind, MAX_CLIP_VERTICES, Manifold, Pose, Real, Vec3, nalgebra,
    reduce_into,
};

/// Number of edge pairs (12 x 12): `Manifold::feature` values of an edge contact are below it,
/// those of a vertex contact start there (B's vertex `v`: `144 + v`; A's vertex `v`: `152 + v`).
pub const EDGE_PAIR_COUNT: u32 = 144;

/// First `Manifold::feature` value of a vertex contact on one of A's vertices.
pub const VERTEX_OF_A_FEATURE: u32 = EDGE_PAIR_COUNT + 8;

/// The contact points before reduction, in world space.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ContactPolygon {
    /// Unit normal from A to B.
    pub normal: Vec3,
    /// Which kind of feature pair made the contact (a vertex contact reports `Edge`).
    pub kind: FeatureKind,
    /// The hysteresis key, as in `Manifold::feature`.
    pub feature: u32,
    /// Storage for the points (midpoints between the surfaces, depth, id).
    pub points: [ContactPoint; MAX_CLIP_VERTICES],
    /// Number of valid points.
    pub len: usize,
}

impl ContactPolygon {
    /// The valid points: up to 8 for a face contact, 1 otherwise.
    pub fn points(&self) -> &[ContactPoint] {
        &self.points[..self.len]
    }

    /// The manifold: the same normal and feature, at most four of the points (Algorithm 8).
    pub fn to_manifold(&self) -> Manifold {
        let mut manifold = Manifold {
            normal: self.normal,
            kind: self.kind,
            feature: self.feature,
            ..Default::default()
        };
        reduce_into(self.points(), &mut manifold);
        manifold
    }
}

/// A contact built on one axis: its separation along that axis, and how far apart its closest
/// pair of surface points is (`+inf` when it has none).
struct Candidate {
    polygon: ContactPolygon,
    separation: Real,
    witness: Real,
}

/// The range of lengths, in m, the narrow phase is specified for: every half extent in it, every
/// coordinate of both translations and the margin at most its upper end. The closest points of
/// two edges divide products of squared lengths, which leave `f32` (overflow to infinity or
/// flush to zero) for lengths far outside it; the world's bounds (1e-3 to 1e3 m boxes within
/// 32 km of the origin) sit well inside. Outside the range a manifold still has one to four
/// finite points and a finite normal, but its geometry (the normal's length included) is not
/// promised.
pub const SUPPORTED_LENGTH: (Real, Real) = (1e-9, 1e9);

/// The thinnest pair the narrow phase is specified for: the smallest of the two boxes' six half
/// extents must be at least this fraction of the largest. Every coordinate of the face clipping
/// is computed in A's frame at the scale of the larger box (its corners, and B's centre, which
/// for boxes that overlap is within both circumradii), where one `f32` step is 6e-8 to 1.2e-7
/// of that size. A slab thinner than about that step cannot be clipped against: its face contact
/// loses every point, the fallback axis is an edge axis parallel to a face normal, and its
/// support edge is picked among tied edges up to the whole large box away (docs/reliability.md,
/// finding 5). Seeded poses of a thin box resting across a large box's face failed up to a
/// ratio of 4e-8 and never from 6.3e-8 on, for large boxes of 1 m to 1.3e7 m; 1e-6 keeps a factor of 16 to 25 from
/// there and contains the world's bounds (1e-3 m boxes next to 1e3 m boxes: exactly 1e-6). The
/// distance between the centres is not part of it: for boxes that overlap it is within the reach
/// of their half extents, and boxes apart accept a contact only when its closest pair of points
/// confirms it, else take the closest vertex pair, which held at every thinness measured (down to
/// 1e-12 of the distance). Outside the ratio, as outside [`SUPPORTED_LENGTH`], a manifold still
/// has one to four finite points and a finite normal, but its geometry is not promised.
pub const SUPPORTED_ASPECT: Real = 1e-6;

/// The contact manifold of box `a` at `pose_a` and box `b` at `pose_b`: `None` when they are more
/// than `margin` apart, else up to four points with a unit normal from A to B. Specified for
/// lengths within [`SUPPORTED_LENGTH`] and pairs no thinner than [`SUPPORTED_ASPECT`].
pub fn collide_cuboids(
    a: &Cuboid,
    pose_a: &Pose,
    b: &Cuboid,
    pose_b: &Pose,
    margin: Real,
) -> Option<Manifold> {
    collide_cuboids_cached(a, pose_a, b, pose_b, margin, None)
}

/// [`collide_cuboids`] with last step's `(kind, feature)` of this pair, whose reference face is
/// kept while it stays within the hysteresis tolerance of the best axis.
pub fn collide_cuboids_cached(
    a: &Cuboid,
    pose_a: &Pose,
    b: &Cuboid,
    pose_b: &Pose,
    margin: Real,
    previous: Option<(FeatureKind, u32)>,
) -> Option<Manifold> {
    contact_polygon(a, pose_a, b, pose_b, margin, previous).map(|p| p.to_manifold())
}

/// The contact [`collide_cuboids_cached`] reduces, before the reduction to four points.
pub fn contact_polygon(
    a: &Cuboid,
    pose_a: &Pose,
    b: &Cuboid,
    pose_b: &Pose,
    margin: Real,
    previous: Option<(FeatureKind, u32)>,
) -> Option<ContactPolygon> {
    let pair = BoxPair::new(a, pose_a, b, pose_b);
    let sat = SatQuery::new(&pair);
    let best = sat.max_separation();
    // The SAT separation never exceeds the distance, so past the margin nothing can touch.
    // A NaN (from a NaN pose) returns here too.
    if best.is_nan() || best > margin {
        return None;
    }
    let chosen = preferred_axis(&pair, &sat, previous).axis;
    let deepest = deepest_axis(&pair, &sat).axis;
    let first = build(&pair, pose_a, pose_b, chosen, margin);

    if best <= 0.0 {
        // Overlap: the deepest axis always has points (its support feature lies over the
        // reference face); a preferred one within tolerance of it almost always does too.
        if first.polygon.len > 0 {
            return Some(first.polygon);
        }
        let second = build(&pair, pose_a, pose_b, deepest, margin);
        return (second.polygon.len > 0).then_some(second.polygon);
    }

    // Apart: a contact built on an SAT axis is right when its closest pair is no farther apart
    // than the separation along that axis: the separation is a lower bound of the distance and
    // the pair an upper bound, so both are the distance and the axis is its direction. If neither
    // the preferred, the deepest nor the best edge axis carries the closest pair, that pair has a
    // vertex on one side, and its own direction is the normal.
    let slack = WITNESS_TOL * pair.noise_scale();
    let exact = |c: &Candidate| c.witness <= c.separation + slack && c.polygon.len > 0;
    if exact(&first) {
        return Some(first.polygon);
    }
    let deepest = build(&pair, pose_a, pose_b, deepest, margin);
    if exact(&deepest) {
        return Some(deepest.polygon);
    }
    let (edge, _) = sat.best_edge();
    let edge = build(&pair, pose_a, pose_b, SatAxis::Edge(edge), margin);
    if exact(&edge) {
        return Some(edge.polygon);
    }
    let vertex = vertex_candidate(&pair, pose_a, slack);
    (vertex.witness <= margin).then_some(vertex.polygon)
}

/// The contact on one SAT axis, in world space.
fn build(pair: &BoxPair, pose_a: &Pose, pose_b: &Pose, axis: SatAxis, margin: Real) -> Candidate {
    let mut polygon = ContactPolygon::default();
    let mut witness = Real::INFINITY;
    let mut separation = Real::NEG_INFINITY;
    match axis {
        SatAxis::FaceA(f) => {
            let c = face_contact(pair, f, margin, KIND_FACE_A);
            polygon.normal = pose_a.rotation * c.normal;
            polygon.kind = FeatureKind::FaceA;
            polygon.feature = f as u32;
            push_in_world(&mut polygon, pose_a, c.points());
            witness = c.min_separation;
            separation = face_a_separation(pair, f);
        }
        SatAxis::FaceB(f) => {
            // The same construction seen from B, whose face is the reference; the contact
            // normal points from A to B, against B's outward face normal.
            let c = face_contact(&pair.swapped(), f, margin, KIND_FACE_B);
            polygon.normal = -(pose_b.rotation * c.normal);
            polygon.kind = FeatureKind::FaceB;
            polygon.feature = f as u32;
            push_in_world(&mut polygon, pose_b, c.points());
            witness = c.min_separation;
            separation = face_b_separation(pair, f);
        }
        SatAxis::Edge(k) => {
            if let Some(n) = edge_axis(pair, k / 3, k % 3) {
                let c = edge_contact(pair, k / 3, k % 3, &n);
                polygon.normal = pose_a.rotation * n;
                polygon.kind = FeatureKind::Edge;
                polygon.feature = c.edge_a as u32 * 12 + c.edge_b as u32;
                if c.depth >= -margin {
                    push(
                        &mut polygon,
                        ContactPoint {
                            position: pose_a * c.midpoint(),
                            depth: c.depth,
                            id: edge_point_id(c.edge_a as u32, c.edge_b as u32),
                        },
                    );
                }
                // The closest pair of two surface segments: a true distance between the boxes'
                // surfaces (used only when they are apart, where it bounds their distance).
                witness = c.closest.distance();
                separation = axis_separation(pair, &n);
            }
        }
    }
    Candidate {
        polygon,
        separation,
        witness,
    }
}

/// The closest vertex pair as a one-point contact along its own direction; none when the pair is
/// too close for that direction to be defined.
fn vertex_candidate(pair: &BoxPair, pose_a: &Pose, min_distance: Real) -> Candidate {
    let v = closest_vertex(pair);
    let mut polygon = ContactPolygon::default();
    if v.distance.is_nan() || v.distance <= min_distance {
        return Candidate {
            polygon,
            separation: Real::NEG_INFINITY,
            witness: Real::INFINITY,
        };
    }
    // From the gap itself: `point_b - point_a` loses the gap's low digits when A's vertex is
    // far larger than the gap (docs/reliability.md, finding 2).
    polygon.normal = pose_a.rotation * (v.gap / v.distance);
    polygon.kind = FeatureKind::Edge;
    polygon.feature = if v.on_a {
        VERTEX_OF_A_FEATURE
    } else {
        EDGE_PAIR_COUNT
    } + v.vertex as u32;
    push(
        &mut polygon,
        ContactPoint {
            position: pose_a * nalgebra::center(&v.point_a, &v.point_b),
            depth: -v.distance,
            id: vertex_point_id(v.vertex as u32, v.on_a),
        },
    );
    Candidate {
        polygon,
        separation: v.distance,
        witness: v.distance,
    }
}

/// Pushes `points`, given in the frame of `pose`, in world coordinates.
fn push_in_world(polygon: &mut ContactPolygon, pose: &Pose, points: &[ContactPoint]) {
    for p in points {
        push(
            polygon,
            ContactPoint {
                position: pose * p.position,
                ..*p
            },
        );
    }
}

fn push(polygon: &mut ContactPolygon, p: ContactPoint) {
    if polygon.len < MAX_CLIP_VERTICES {
        polygon.points[polygon.len] = p;
        polygon.len += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tests::{MARGIN, at, crossed_edges, cube, cube_on_slab};
    use tumble_geometry::Rot;

    #[test]
    fn a_box_resting_on_a_slab_gets_four_points_on_the_slab_face() {
        // Cube bottom 2 mm below the slab top (y = 0.5).
        let m = cube_on_slab(1.0, 0.998, 0.0).expect("overlapping boxes touch");
        assert_eq!((m.kind, m.feature, m.len), (FeatureKind::FaceA, 2, 4));
        assert_eq!(m.normal, Vec3::y());
        for p in m.points() {
            // Depth 2 mm, midpoint 1 mm below the slab top; f32 rounding of 0.998 - 0.5.
            assert!((p.depth - 0.002).abs() < 1e-6 && (p.position.y - 0.499).abs() < 1e-6);
        }
    }

    #[test]
    fn the_normal_points_from_a_to_b_when_b_holds_the_reference_face() {
        // A small box under a big one: the big box (B) has the better face.
        let small = cube(0.5);
        let big = Cuboid::new(Vec3::new(5.0, 0.5, 5.0));
        let m = collide_cuboids(
            &small,
            &Pose::translation(0.0, -0.998, 0.0),
            &big,
            &Pose::identity(),
            MARGIN,
        )
        .expect("overlapping boxes touch");
        // Both faces tie on depth; A's face wins ties, and either way the normal is +y (A to B).
        assert!((m.normal - Vec3::y()).norm() < 1e-6);
        let tilted = at(0.0, -1.02, 0.0, Rot::from_euler_angles(0.0, 0.0, 0.05));
        let m = collide_cuboids(&small, &tilted, &big, &Pose::identity(), MARGIN)
            .expect("the tilted corner dips in");
        // Tilted A: B's bottom face is now the reference, the normal still runs from A to B.
        assert_eq!(m.kind, FeatureKind::FaceB);
        assert!((m.normal - Vec3::y()).norm() < 1e-6);
        assert!(m.points().iter().all(|p| p.depth >= -MARGIN));
    }

    #[test]
    fn crossed_edges_give_one_point_with_the_overlap_as_depth() {
        let (pose_a, pose_b) = crossed_edges(0.5, -0.01);
        let m = collide_cuboids(&cube(0.5), &pose_a, &cube(0.5), &pose_b, MARGIN)
            .expect("the edges cross 1 cm deep");
        assert_eq!((m.kind, m.len), (FeatureKind::Edge, 1));
        assert!((m.normal - Vec3::y()).norm() < 1e-5);
        assert!((m.points()[0].depth - 0.01).abs() < 1e-5);
    }

    #[test]
    fn corners_apart_diagonally_get_the_euclidean_gap_and_direction() {
        // Gap vector (0.006, 0.008, 0): 1 cm, though every SAT axis sees at most 8 mm.
        let m = collide_cuboids(
            &cube(0.5),
            &Pose::identity(),
            &cube(0.5),
            &Pose::translation(1.006, 1.008, 0.0),
            MARGIN,
        )
        .expect("1 cm apart is within the 2 cm margin");
        assert_eq!(m.len, 1);
        assert!((m.points()[0].depth + 0.01).abs() < 1e-6);
        assert!((m.normal - Vec3::new(0.6, 0.8, 0.0)).norm() < 1e-4);
        // 2.5 cm apart diagonally: the SAT axes see 2 cm at most, but the boxes are beyond the margin.
        let far = Pose::translation(1.015, 1.02, 0.0);
        assert!(collide_cuboids(&cube(0.5), &Pose::identity(), &cube(0.5), &far, MARGIN).is_none());
    }

    #[test]
    fn last_steps_reference_face_is_kept_and_renames_nothing() {
        let a = cube(0.5);
        let rot = Rot::from_euler_angles(0.0, 0.0, 0.004);
        let pose_b = at(0.25, 0.999, 0.25, rot);
        let fresh = collide_cuboids(&a, &Pose::identity(), &a, &pose_b, MARGIN).expect("touching");
        let other = if fresh.kind == FeatureKind::FaceA {
            (FeatureKind::FaceB, 3)
        } else {
            (FeatureKind::FaceA, 2)
        };
        let kept = collide_cuboids_cached(&a, &Pose::identity(), &a, &pose_b, MARGIN, Some(other))
            .expect("touching");
        assert_eq!((kept.kind, kept.feature), other);
        assert!((kept.normal - Vec3::y()).norm() < 0.01);
    }
}
