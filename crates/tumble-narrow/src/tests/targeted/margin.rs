//! The margin.

use super::*;

#[test]
fn the_margin_is_inclusive_and_a_cutoff() {
    // Aligned cubes whose faces are exactly 2^-6 apart (exact binary fractions): a contact at a
    // margin of 2^-6, its four points exactly that far apart; none at a margin a hair smaller.
    let gap = 1.0 / 64.0;
    let pose_b = Pose::translation(0.25, 1.0 + gap, -0.125);
    let m = collide_cuboids(&cube(0.5), &Pose::identity(), &cube(0.5), &pose_b, gap)
        .expect("a gap equal to the margin is within it");
    assert_eq!((m.kind, m.feature, m.len), (FeatureKind::FaceA, 2, 4));
    assert!(m.points().iter().all(|p| p.depth == -gap));
    let below = gap * (1.0 - Real::EPSILON);
    assert!(collide_cuboids(&cube(0.5), &Pose::identity(), &cube(0.5), &pose_b, below).is_none());
    // The face contact's own margin: above its face plane by more than the margin, a point is
    // dropped, though its separation still counts.
    let pair = BoxPair::new(&cube(0.5), &Pose::identity(), &cube(0.5), &pose_b);
    let c = face_contact(&pair, 2, gap, KIND_FACE_A);
    assert_eq!(c.len, 4);
    assert_eq!(c.min_separation, gap);
    let c = face_contact(&pair, 2, below, KIND_FACE_A);
    assert_eq!(c.len, 0);
    assert_eq!(c.min_separation, gap);
}

#[test]
fn face_contact_reports_its_frame_incident_face_and_separation() {
    // B turned 0.1 rad about z over A's top face, 5 mm apart at its lowest corner: the reference
    // normal is A's +y, the incident face B's -y (3), and the smallest separation over the clip
    // is the 5 mm of that corner.
    let rot = Rot::from_euler_angles(0.0, 0.0, 0.1);
    let low = (rot * Vec3::new(-0.5, -0.5, 0.0))
        .y
        .min((rot * Vec3::new(0.5, -0.5, 0.0)).y);
    let pose_b = at(0.1, 0.5 + 0.005 - low, 0.2, rot);
    let pair = BoxPair::new(&cube(0.5), &Pose::identity(), &cube(0.5), &pose_b);
    let c = face_contact(&pair, 2, MARGIN, KIND_FACE_A);
    assert_eq!((c.normal, c.incident_face), (Vec3::y(), 3));
    assert!((c.min_separation - 0.005).abs() < 1e-6);
    // The clip runs from B's low edge to A's side plane x = 0.5, about 0.85 m across, along which
    // B's face rises by tan(0.1) = 10 %: the far side is beyond the 2 cm margin, and only the two
    // points of the low edge remain, each 5 mm apart.
    assert_eq!(c.len, 2);
    assert!(c.points().iter().all(|p| (p.depth + 0.005).abs() < 1e-6));
    // Seen from B (the pair swapped), B's bottom face as reference: its normal is B's -y, the
    // incident face A's +y (2).
    let c = face_contact(&pair.swapped(), 3, MARGIN, KIND_FACE_B);
    assert_eq!((c.normal, c.incident_face), (-Vec3::y(), 2));
    assert!(c.len >= 1);
    assert!(c.points().iter().all(|p| id_kind(p.id) == KIND_FACE_B));
}

#[test]
fn a_contact_polygon_keeps_up_to_eight_points_and_the_manifold_four() {
    // A cube turned 45 degrees about y sunk 5 mm into an unturned one: its bottom square clipped
    // by the other's top square is an octagon, all 8 points 5 mm deep.
    let turned = at(
        0.0,
        0.995,
        0.0,
        Rot::from_euler_angles(0.0, std::f32::consts::FRAC_PI_4, 0.0),
    );
    let polygon = contact_polygon(
        &cube(0.5),
        &Pose::identity(),
        &cube(0.5),
        &turned,
        MARGIN,
        None,
    )
    .expect("overlap");
    assert_eq!(polygon.len, 8);
    assert!(
        polygon
            .points()
            .iter()
            .all(|p| (p.depth - 0.005).abs() < 1e-6)
    );
    let m = polygon.to_manifold();
    assert_eq!(
        (m.len, m.normal, m.kind, m.feature),
        (4, polygon.normal, polygon.kind, polygon.feature)
    );
    assert_eq!(
        collide_cuboids(&cube(0.5), &Pose::identity(), &cube(0.5), &turned, MARGIN),
        Some(m)
    );
}

#[test]
fn a_face_whose_clip_lies_beyond_the_margin_is_no_contact_even_when_it_is_exact() {
    // B turned 0.1 rad about z, its lowest edge (along z) `g` above A's top face and `delta`
    // beyond A's -x side, so that the clipped part of B's bottom face starts `delta tan(0.1)` =
    // 0.7 um higher than the edge: beyond the margin, though within the witness tolerance
    // (1e-6 for these cubes) of the face's separation. The boxes are then sqrt(g^2 + delta^2)
    // apart, A's top left edge to B's low edge: within the margin, so there is a contact, with a
    // point, at that distance.
    let (theta, g, delta): (Real, Real, Real) = (0.1, MARGIN - 0.35e-6, 7e-6);
    let rot = Rot::from_euler_angles(0.0, 0.0, theta);
    let edge = rot * Vec3::new(-0.5, -0.5, 0.0);
    let pose_b = at(-0.5 - delta - edge.x, 0.5 + g - edge.y, 0.0, rot);
    let (a, b) = (cube(0.5), cube(0.5));
    let pair = BoxPair::new(&a, &Pose::identity(), &b, &pose_b);
    let sat = SatQuery::new(&pair);
    // The premises, in the narrow phase's own f32 numbers: A's top face is preferred and within
    // the margin, its clip has no point within the margin, and its nearest clipped point is
    // within the witness tolerance of its separation.
    assert_eq!(preferred_axis(&pair, &sat, None).axis, SatAxis::FaceA(2));
    let separation = crate::face_a_separation(&pair, 2);
    assert!(sat.max_separation() <= MARGIN && separation <= MARGIN);
    let face = face_contact(&pair, 2, MARGIN, KIND_FACE_A);
    assert_eq!(face.len, 0);
    assert!(face.min_separation > MARGIN);
    assert!(face.min_separation <= separation + WITNESS_TOL * pair.noise_scale());
    let m = collide_cuboids(&a, &Pose::identity(), &b, &pose_b, MARGIN).expect("within the margin");
    assert!(m.len >= 1);
    // The distance of two f32 edges about 1 apart: 1e-6.
    let distance = (g * g + delta * delta).sqrt();
    assert!((m.max_depth() + distance).abs() < 1e-6, "{m:?}");
}

#[test]
fn a_kept_face_whose_incident_face_misses_it_falls_back_to_the_deepest_axis() {
    // B turned 40 degrees about z, its lowest edge (along z) `e` beyond A's +x side and `d`
    // below A's top face. Its down-left face (its -x, outward normal (-cos, -sin, 0)) dips over
    // A's top right edge, which it overlaps by (d - e cot 40) sin 40 = 1.039 mm: the deepest
    // axis, B's face 1. A's top face overlaps by d = 4 mm, 2.96 mm worse: within the hysteresis
    // tolerance (5 % of 1 mm plus 1 % of 0.5 = 5.05 mm), so last step's A face 2 is kept. But
    // its incident face is B's down-right one (its -y: at 40 degrees it faces down more than
    // the other), which lies entirely beyond A's side: the clip is empty, and the contact must
    // come from the deepest axis instead.
    let (phi, d, e): (Real, Real, Real) = (40f32.to_radians(), 0.004, 0.002);
    let rot = Rot::from_euler_angles(0.0, 0.0, phi);
    let low = rot * Vec3::new(-0.5, -0.5, 0.0);
    let pose_b = at(0.5 + e - low.x, 0.5 - d - low.y, 0.0, rot);
    let (a, b) = (cube(0.5), cube(0.5));
    let overlap = (d - e / phi.tan()) * phi.sin();
    let pair = BoxPair::new(&a, &Pose::identity(), &b, &pose_b);
    let sat = SatQuery::new(&pair);
    // The premises: the deepest axis is B's face 1 (or A's z edges crossed with B's y edges,
    // the same axis: for a turn about z every edge cross product is a face normal, and rounding
    // decides which of the two comes out ahead), A's face 2 is kept, and it has no points.
    // (f32 coordinates below 1: 1e-6.)
    let deepest = deepest_axis(&pair, &sat);
    assert!(
        matches!(deepest.axis, SatAxis::FaceB(1) | SatAxis::Edge(7)),
        "{deepest:?}"
    );
    assert!(
        (deepest.separation + overlap).abs() < 1e-6,
        "{deepest:?} {overlap}"
    );
    let previous = Some((FeatureKind::FaceA, 2));
    assert_eq!(
        preferred_axis(&pair, &sat, previous).axis,
        SatAxis::FaceA(2)
    );
    assert_eq!(face_contact(&pair, 2, MARGIN, KIND_FACE_A).len, 0);
    // Without history B's face 1 is the contact (it beats A's by far more than the face
    // tolerance). With the history the contact is the deepest axis's. Either way: points, the
    // deepest as deep as the overlap, the normal from A to B against B's outward (-cos, -sin, 0).
    let fresh = collide_cuboids(&a, &Pose::identity(), &b, &pose_b, MARGIN);
    assert_eq!(kind_and_feature(fresh), Some((FeatureKind::FaceB, 1)));
    for prev in [None, previous] {
        let m = collide_cuboids_cached(&a, &Pose::identity(), &b, &pose_b, MARGIN, prev)
            .expect("overlap");
        assert_ne!((m.kind, m.feature), (FeatureKind::FaceA, 2), "{prev:?}");
        assert!(m.len >= 1);
        assert!((m.max_depth() - overlap).abs() < 1e-6);
        assert!((m.normal - Vec3::new(phi.cos(), phi.sin(), 0.0)).norm() < 1e-6);
    }
}

#[test]
fn a_nan_pose_gives_no_contact() {
    // A NaN rotation makes every separation NaN, a NaN coordinate some of them: neither may
    // produce a manifold (whose NaN normal and points would poison the solver).
    let nan_rot = Rot::new_unchecked(tumble_geometry::nalgebra::Quaternion::new(
        Real::NAN,
        0.0,
        0.0,
        0.0,
    ));
    for pose_b in [
        at(0.0, 0.9, 0.0, nan_rot),
        at(Real::NAN, 0.9, 0.0, Rot::identity()),
    ] {
        for (a, pa, b, pb) in [
            (cube(0.5), Pose::identity(), cube(0.5), pose_b),
            (cube(0.5), pose_b, cube(0.5), Pose::identity()),
        ] {
            let m = collide_cuboids(&a, &pa, &b, &pb, MARGIN);
            assert!(m.is_none(), "{m:?}");
        }
    }
}
