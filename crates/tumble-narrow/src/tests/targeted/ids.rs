//! Feature ids and vertex contacts.

use super::*;

#[test]
fn crossed_edges_pack_their_pair_into_the_feature_and_the_id() {
    // A's highest edge runs along its z with local x and y both positive: edge 4 * 2 + 1 + 2 =
    // 11 in the `CUBOID_EDGES` numbering. B's lowest runs along its x with local y negative and
    // z positive: 4 * 0 + 0 + 2 = 2. The feature is 11 * 12 + 2, the id kind 2 with A's edge in
    // bits 4-7 and B's in bits 0-3.
    for gap in [-0.01, 0.01] {
        let (pose_a, pose_b) = crossed_edges(0.5, gap);
        let m = collide_cuboids(&cube(0.5), &pose_a, &cube(0.5), &pose_b, MARGIN)
            .expect("within the margin");
        assert_eq!((m.kind, m.feature, m.len), (FeatureKind::Edge, 134, 1));
        assert_eq!(m.points()[0].id, (2 << 14) | (11 << 4) | 2);
        assert_eq!(m.points()[0].id, edge_point_id(11, 2));
        assert_eq!(id_kind(m.points()[0].id), KIND_EDGE);
        // The depth is minus the gap, the point midway at x = z = 0; f32: 1e-5.
        let p = m.points()[0];
        assert!((p.depth + gap).abs() < 1e-5);
        // A's top edge is at height sqrt(2) / 2, B's bottom edge `gap` above it.
        let mid = 0.5 * (2f32.sqrt() + gap);
        assert!((p.position - Point3::new(0.0, mid, 0.0)).norm() < 1e-5);
        assert!((m.normal - Vec3::y()).norm() < 1e-5);
    }
    // 3 cm apart with a 2 cm margin: nothing (every SAT axis sees at most the 3 cm).
    let (pose_a, pose_b) = crossed_edges(0.5, 0.03);
    assert!(collide_cuboids(&cube(0.5), &pose_a, &cube(0.5), &pose_b, MARGIN).is_none());
}

#[test]
fn id_fields_land_in_their_documented_bits() {
    assert_eq!(
        face_point_id(KIND_FACE_A, 5, 4, 7, 6),
        (5 << 11) | (4 << 8) | (7 << 4) | 6
    );
    assert_eq!(
        face_point_id(KIND_FACE_B, 1, 2, 3, 4),
        (1 << 14) | (1 << 11) | (2 << 8) | (3 << 4) | 4
    );
    assert_eq!(edge_point_id(11, 7), (2 << 14) | (11 << 4) | 7);
    assert_eq!(vertex_point_id(6, false), (3 << 14) | 6);
    assert_eq!(vertex_point_id(6, true), (3 << 14) | (1 << 4) | 6);
    for (id, kind) in [
        (face_point_id(KIND_FACE_A, 2, 3, 1, 2), KIND_FACE_A),
        (face_point_id(KIND_FACE_B, 2, 3, 1, 2), KIND_FACE_B),
        (edge_point_id(3, 4), KIND_EDGE),
        (vertex_point_id(3, true), KIND_VERTEX),
    ] {
        assert_eq!(id_kind(id), kind);
    }
    assert_eq!(
        (EDGE_PAIR_COUNT, VERTEX_OF_A_FEATURE, SIDE_LABEL_BASE),
        (144, 152, 4)
    );
}

#[test]
fn a_box_resting_inside_a_face_gets_its_four_bottom_corners_as_ids() {
    // A small aligned cube well inside a slab's top face, 2 mm deep: the four corners of its
    // bottom face (3: corners 0, 1, 5, 4) are incident corners, labelled (k - 1, k) for corner
    // k; reference face 2, incident face 3, kind 0.
    let m = cube_on_slab(1.0, 0.998, -1.0).expect("overlap");
    let mut ids: Vec<u32> = m.points().iter().map(|p| p.id).collect();
    ids.sort_unstable();
    let mut want: Vec<u32> = (0..4u32)
        .map(|k| face_point_id(KIND_FACE_A, 2, 3, (k + 3) % 4, k))
        .collect();
    want.sort_unstable();
    assert_eq!(ids, want);
    // Each id's corner is where the point is: corner k of face 3 is vertex [0, 1, 5, 4][k].
    let bottom = [0, 1, 5, 4];
    for p in m.points() {
        let k = (p.id & 15) as usize;
        let v = cube(0.5).vertex(bottom[k]) + Vec3::new(1.0, 0.998, -1.0);
        // The point is 1 mm above the cube's corner (midway to the slab's face); f32: 1e-6.
        assert!((p.position - (v + Vec3::new(0.0, 0.001, 0.0))).norm() < 1e-6);
    }
}

// ---------------------------------------------------------------------------------------------
// Vertex contacts.

/// An unturned cube A of half size 0.5, and a turned cube B (half size 0.3) whose vertex nearest
/// to A is 1 cm from A's edge along z at x = y = 0.5, in the direction `u` 45 degrees from x in
/// the xy plane. B's vertex is its support along `-u` (B lies beyond the plane through it normal
/// to `u`), A's edge its support along `u`: the gap is 1 cm along `u`, the direction of no SAT
/// axis (no face normal or edge cross product of these two boxes lies along `u`), so the contact
/// is the vertex pair.
fn corner_near_edge() -> (Pose, usize, Vec3, Point3) {
    let u = Vec3::new(1.0, 1.0, 0.0).normalize();
    let rot = Rot::from_euler_angles(0.2, 1.1, 0.4);
    let local = rot.inverse() * -u;
    let v = (0..3)
        .map(|k| usize::from(local[k] > 0.0) << k)
        .sum::<usize>();
    let corner = cube(0.3).vertex(v);
    let on_a = Point3::new(0.5, 0.5, 0.1);
    let target = on_a + u * 0.01;
    let centre = target - rot * corner.coords;
    (
        Pose::from_parts(Translation3::from(centre.coords), rot),
        v,
        u,
        on_a,
    )
}

#[test]
fn a_corner_apart_from_an_edge_is_a_vertex_contact_named_by_its_vertex() {
    let (pose_b, v, u, on_a) = corner_near_edge();
    let (a, b) = (cube(0.5), cube(0.3));
    // The premise: every SAT axis sees less than the 1 cm gap, by 15 % (the nearest, an edge
    // cross product in the xy plane, is some 32 degrees off `u`): none carries it.
    let pair = BoxPair::new(&a, &Pose::identity(), &b, &pose_b);
    assert!(SatQuery::new(&pair).max_separation() < 0.0086);
    let c = closest_vertex(&pair);
    assert_eq!((c.vertex, c.on_a), (v, false));
    assert!((c.distance - 0.01).abs() < 1e-6);

    let m = collide_cuboids(&a, &Pose::identity(), &b, &pose_b, MARGIN).expect("1 cm apart");
    assert_eq!(
        (m.kind, m.feature, m.len),
        (FeatureKind::Edge, 144 + v as u32, 1)
    );
    let p = m.points()[0];
    assert_eq!(p.id, (3 << 14) | v as u32);
    // The gap of 1 cm in f32 coordinates of 0.5: 1e-6 on the depth and the midpoint, and the
    // direction of a 1 cm vector known to 1e-7 in each coordinate: 1e-4.
    assert!((p.depth + 0.01).abs() < 1e-6);
    assert!((p.position - (on_a + u * 0.005)).norm() < 1e-6);
    assert!((m.normal - u).norm() < 1e-4);

    // The other way round the vertex is the first box's: 152 + v, the normal reversed.
    let m = collide_cuboids(&b, &pose_b, &a, &Pose::identity(), MARGIN).expect("1 cm apart");
    assert_eq!(
        (m.kind, m.feature, m.len),
        (FeatureKind::Edge, 152 + v as u32, 1)
    );
    let p = m.points()[0];
    assert_eq!(p.id, (3 << 14) | (1 << 4) | v as u32);
    assert!((p.depth + 0.01).abs() < 1e-6);
    assert!((p.position - (on_a + u * 0.005)).norm() < 1e-6);
    assert!((m.normal + u).norm() < 1e-4);
    let swapped = BoxPair::new(&b, &pose_b, &a, &Pose::identity());
    let c = closest_vertex(&swapped);
    assert_eq!((c.vertex, c.on_a), (v, true));
    // Its point on the other box is A's edge point, seen from B's frame.
    let on_a_in_b = pose_b.inverse_transform_point(&on_a);
    assert!((c.point_b - on_a_in_b).norm() < 1e-6);
    assert!(((c.point_b - c.point_a).norm() - 0.01).abs() < 1e-6);

    // 2.25 cm away, beyond the 2 cm margin, though the SAT axes all see less (at most 85 %,
    // 1.9 cm): nothing.
    let far = Pose::from_parts(
        Translation3::from(pose_b.translation.vector + u * 0.0125),
        pose_b.rotation,
    );
    assert!(
        SatQuery::new(&BoxPair::new(&a, &Pose::identity(), &b, &far)).max_separation() < MARGIN
    );
    assert!(collide_cuboids(&a, &Pose::identity(), &b, &far, MARGIN).is_none());
    assert!(collide_cuboids(&b, &far, &a, &Pose::identity(), MARGIN).is_none());
}
