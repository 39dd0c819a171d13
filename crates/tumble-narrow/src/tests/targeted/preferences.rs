//! Preferences and hysteresis.

use super::*;

/// Two cubes of half size 0.5: A unturned at the origin, B turned by `theta` about z with its
/// centre at lateral offset `x0` and raised so that A's top face separates by `separation_a`
/// (negative: overlap). By hand, with `s, c` the sine and cosine of `theta`:
/// - A's top face (+y): `y0 - 0.5 - 0.5 (s + c)`;
/// - B's bottom face (its `-y`, normal `(s, -c, 0)`): `(-x0 s + y0 c) - 0.5 - 0.5 (s + c)`;
///
/// so A's face beats B's by `y0 (1 - c) + x0 s`.
struct Tilted {
    pose_b: Pose,
    separation_a: f64,
    separation_b: f64,
}

fn tilted(theta: f64, x0: f64, separation_a: f64) -> Tilted {
    let (s, c) = theta.sin_cos();
    let y0 = separation_a + 0.5 + 0.5 * (s + c);
    Tilted {
        pose_b: at(
            x0 as Real,
            y0 as Real,
            0.0,
            Rot::from_euler_angles(0.0, 0.0, theta as Real),
        ),
        separation_a,
        separation_b: (-x0 * s + y0 * c) - 0.5 - 0.5 * (s + c),
    }
}

/// The hysteresis tolerance of the cube pair at best separation `best`: 5 % of it plus 1 % of
/// the feature scale (0.5).
pub(super) fn hysteresis(best: f64) -> f64 {
    HYSTERESIS_REL_TOL as f64 * best.abs() + HYSTERESIS_ABS_TOL as f64 * 0.5
}

#[test]
fn last_steps_face_is_kept_within_the_hysteresis_tolerance_and_dropped_beyond_it() {
    let (theta, best) = (1f64.to_radians(), -0.001);
    let slack = hysteresis(best);
    let (s, c) = theta.sin_cos();
    let y0 = best + 0.5 + 0.5 * (s + c);
    for (fraction, kept) in [(0.9, true), (1.1, false)] {
        // The lateral offset at which A's face beats B's by `fraction` of the tolerance.
        let x0 = (fraction * slack - y0 * (1.0 - c)) / s;
        let t = tilted(theta, x0, best);
        assert!(((t.separation_a - t.separation_b) / slack - fraction).abs() < 1e-6);
        let (a, b) = (cube(0.5), cube(0.5));
        let fresh = collide_cuboids(&a, &Pose::identity(), &b, &t.pose_b, MARGIN);
        // Without history A's face, the best, is the reference.
        assert_eq!(kind_and_feature(fresh), Some((FeatureKind::FaceA, 2)));
        let previous = Some((FeatureKind::FaceB, 3));
        let m = collide_cuboids_cached(&a, &Pose::identity(), &b, &t.pose_b, MARGIN, previous)
            .expect("overlapping");
        if kept {
            assert_eq!((m.kind, m.feature), (FeatureKind::FaceB, 3));
            // B's face normal, from A to B: B's local +y, (-s, c, 0); f32 rotation: 1e-6.
            assert!((m.normal - Vec3::new(-s as Real, c as Real, 0.0)).norm() < 1e-6);
            // Depths along B's face: at most B's face overlap, within f32 rounding.
            assert!(m.max_depth() as f64 <= -t.separation_b + 1e-6);
        } else {
            assert_eq!(Some((m.kind, m.feature)), kind_and_feature(fresh));
        }
        // The same pair the other way round: B's (the unturned cube's) top face is then the
        // best and A's bottom face the one kept or dropped.
        let fresh = collide_cuboids(&b, &t.pose_b, &a, &Pose::identity(), MARGIN);
        assert_eq!(kind_and_feature(fresh), Some((FeatureKind::FaceB, 2)));
        let previous = Some((FeatureKind::FaceA, 3));
        let m = collide_cuboids_cached(&b, &t.pose_b, &a, &Pose::identity(), MARGIN, previous);
        let expected = if kept {
            previous
        } else {
            kind_and_feature(fresh)
        };
        assert_eq!(kind_and_feature(m), expected);
        // preferred_axis, directly.
        let pair = BoxPair::new(&a, &Pose::identity(), &b, &t.pose_b);
        let sat = SatQuery::new(&pair);
        let chosen = preferred_axis(&pair, &sat, Some((FeatureKind::FaceB, 3))).axis;
        let expected = if kept {
            SatAxis::FaceB(3)
        } else {
            SatAxis::FaceA(2)
        };
        assert_eq!(chosen, expected, "fraction {fraction}");
        let chosen = preferred_axis(&pair, &sat, Some((FeatureKind::FaceA, 2))).axis;
        assert_eq!(chosen, SatAxis::FaceA(2));
    }
}

#[test]
fn a_far_worse_previous_face_is_dropped() {
    // Turned 17 degrees: A's face beats B's by y0 (1 - c) + 0 = 0.05, ten times the tolerance.
    let t = tilted(0.3, 0.0, -0.001);
    assert!(t.separation_a - t.separation_b > 9.0 * hysteresis(t.separation_a));
    let (a, b) = (cube(0.5), cube(0.5));
    for previous in [
        (FeatureKind::FaceB, 3),
        (FeatureKind::FaceA, 3),
        (FeatureKind::FaceA, 0),
    ] {
        let m =
            collide_cuboids_cached(&a, &Pose::identity(), &b, &t.pose_b, MARGIN, Some(previous));
        assert_eq!(
            kind_and_feature(m),
            Some((FeatureKind::FaceA, 2)),
            "{previous:?}"
        );
    }
}

#[test]
fn a_history_that_names_no_face_is_ignored() {
    // Close enough that a valid face of B would be kept (see the test above), so that only
    // the validity of the key decides.
    let t = tilted(1f64.to_radians(), 0.0, -0.001);
    let (a, b) = (cube(0.5), cube(0.5));
    let fresh = collide_cuboids(&a, &Pose::identity(), &b, &t.pose_b, MARGIN);
    for previous in [
        (FeatureKind::Edge, 3),
        (FeatureKind::Edge, EDGE_PAIR_COUNT + 1),
        (FeatureKind::FaceA, 6),
        (FeatureKind::FaceB, 6),
        (FeatureKind::FaceA, 200),
        (FeatureKind::FaceB, 9),
    ] {
        let m =
            collide_cuboids_cached(&a, &Pose::identity(), &b, &t.pose_b, MARGIN, Some(previous));
        assert_eq!(m, fresh, "{previous:?}");
    }
    let kept = collide_cuboids_cached(
        &a,
        &Pose::identity(),
        &b,
        &t.pose_b,
        MARGIN,
        Some((FeatureKind::FaceB, 3)),
    );
    assert_eq!(kind_and_feature(kept), Some((FeatureKind::FaceB, 3)));
}

#[test]
fn b_face_is_the_reference_only_when_it_beats_a_by_the_face_tolerance() {
    // Equal faces (aligned cubes): A's, however the rounding falls.
    let (a, b) = (cube(0.5), cube(0.5));
    let m = collide_cuboids(
        &a,
        &Pose::identity(),
        &b,
        &Pose::translation(0.1, 0.999, 0.2),
        MARGIN,
    );
    assert_eq!(kind_and_feature(m), Some((FeatureKind::FaceA, 2)));
    // B's face better by 0.05 (the turned cube seen the other way round): B's.
    let t = tilted(0.3, 0.0, -0.001);
    let m = collide_cuboids(&b, &t.pose_b, &a, &Pose::identity(), MARGIN).expect("overlap");
    assert_eq!((m.kind, m.feature), (FeatureKind::FaceB, 2));
    assert!(
        (m.normal + Vec3::y()).norm() < 1e-6,
        "from A (turned, above) down to B"
    );
    // B's face better by less than the tolerance, 2e-3 * 0.001 + 2e-5 * 0.5 = 1.2e-5: a tilt of
    // 1e-3 rad costs y0 (1 - cos) = 5e-7 only. A's.
    let t = tilted(1e-3, 0.0, -0.001);
    let face_b_tol = FACE_B_REL_TOL as f64 * t.separation_b.abs() + FACE_B_ABS_TOL as f64 * 0.5;
    assert!(t.separation_a - t.separation_b < 0.1 * face_b_tol);
    let m = collide_cuboids(&b, &t.pose_b, &a, &Pose::identity(), MARGIN);
    assert_eq!(kind_and_feature(m), Some((FeatureKind::FaceA, 3)));
}

/// Two cubes of half size 0.5, B turned by `roll` about x and `yaw` about z (degrees), its
/// centre over A's top face at `(x0, ., z0)`, lowered until the largest SAT separation is
/// `-depth` (bisection on the exact separations).
fn resting(roll: f64, yaw: f64, x0: Real, z0: Real, depth: f64) -> Pose {
    let rot = Rot::from_euler_angles(roll.to_radians() as Real, 0.0, yaw.to_radians() as Real);
    let (mut lo, mut hi) = (0.0, 2.0);
    let pose = |y: f64| at(x0, y as Real, z0, rot);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        let (a, b) = (
            Box64::new(&cube(0.5), &Pose::identity()),
            Box64::new(&cube(0.5), &pose(mid)),
        );
        if Spec::new(&a, &b, MARGIN as f64, 0.0).sat.max() < -depth {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    pose(0.5 * (lo + hi))
}

/// For B at `pose_b` on an unturned cube A: the deepest edge axis, how much it beats the best
/// face by, its angle (degrees) from A's and from B's face normal, and the two tolerances.
fn edge_premise(pose_b: &Pose) -> (usize, f64, f64, f64, f64, f64) {
    let (a, b) = (
        Box64::new(&cube(0.5), &Pose::identity()),
        Box64::new(&cube(0.5), pose_b),
    );
    let spec = Spec::new(&a, &b, MARGIN as f64, 0.0);
    let Ok(Axis::Edge(e)) = spec.deepest() else {
        panic!("the deepest axis is an edge")
    };
    let n = spec.normal(Axis::Edge(e)).expect("not parallel");
    let best_face = best_of(&spec.sat.face_a).1.max(best_of(&spec.sat.face_b).1);
    let angle = |m: &V64| n.dot(m).abs().acos().to_degrees();
    let edge_tol = EDGE_REL_TOL as f64 * best_face.abs() + EDGE_ABS_TOL as f64 * 0.5;
    (
        e,
        spec.sat.edge[e].expect("not parallel") - best_face,
        angle(&V64::y()),
        angle(&b.axes[1]),
        edge_tol,
        hysteresis(best_face),
    )
}

#[test]
fn an_edge_near_a_face_normal_yields_to_the_face_while_shallow() {
    // Turned 1 degree about x and z, 1 mm deep: the deepest axis is an edge crossing, 1 degree
    // from A's face normal, beating the best face by more than 3 edge tolerances but by less
    // than half the hysteresis tolerance. Face-like: A's face, with its four points.
    let shallow = resting(1.0, 1.0, 0.1, 0.1, 0.001);
    let (e, beat, angle, _, edge_tol, hyst) = edge_premise(&shallow);
    assert!(
        angle < 2.0 && beat > 3.0 * edge_tol && beat < 0.5 * hyst,
        "{beat} {angle}"
    );
    let m = collide_cuboids(&cube(0.5), &Pose::identity(), &cube(0.5), &shallow, MARGIN)
        .expect("overlap");
    // Several points (how many the clip leaves within the margin, the random test checks
    // exactly): B's face tilts by about 1.4 degrees, so its corner farthest from the deepest one
    // is some 3 cm higher, beyond the margin, the two others within it.
    assert_eq!((m.kind, m.feature), (FeatureKind::FaceA, 2));
    assert!(m.len >= 3, "{m:?}");
    let pair = BoxPair::new(&cube(0.5), &Pose::identity(), &cube(0.5), &shallow);
    let sat = SatQuery::new(&pair);
    assert_eq!(preferred_axis(&pair, &sat, None).axis, SatAxis::FaceA(2));
    assert_eq!(deepest_axis(&pair, &sat).axis, SatAxis::Edge(e));
    // Seen the other way round the same holds with B's face (A's top is then B's face 2).
    let m = collide_cuboids(&cube(0.5), &shallow, &cube(0.5), &Pose::identity(), MARGIN)
        .expect("overlap");
    assert!(
        matches!(m.kind, FeatureKind::FaceA | FeatureKind::FaceB),
        "{m:?}"
    );

    // The same tilt 5 cm deep, beyond 5 % of the feature scale (2.5 cm): the edge, which beats
    // the faces by more than the edge tolerance, is the contact.
    let deep = resting(1.0, 1.0, 0.1, 0.1, 0.05);
    assert!(0.05 > FACE_LIKE_MAX_DEPTH as f64 * 0.5);
    let (e, beat, angle, _, edge_tol, hyst) = edge_premise(&deep);
    assert!(
        angle < 2.0 && beat > 3.0 * edge_tol && beat < 0.5 * hyst,
        "{beat} {angle}"
    );
    let m =
        collide_cuboids(&cube(0.5), &Pose::identity(), &cube(0.5), &deep, MARGIN).expect("overlap");
    assert_eq!((m.kind, m.len), (FeatureKind::Edge, 1));
    let pair = BoxPair::new(&cube(0.5), &Pose::identity(), &cube(0.5), &deep);
    assert_eq!(
        preferred_axis(&pair, &SatQuery::new(&pair), None).axis,
        SatAxis::Edge(e)
    );
    assert!((m.points()[0].depth - 0.05).abs() < 1e-5);
}

#[test]
fn an_edge_beyond_three_degrees_of_the_face_normal_wins_by_the_edge_tolerance() {
    // Turned 4 degrees about x and z, 1 mm deep: the edge is 4 degrees from A's face normal,
    // no longer face-like, and beats the faces by more than the edge tolerance (while still by
    // less than the hysteresis one): the edge.
    let pose = resting(4.0, 4.0, 0.1, 0.1, 0.001);
    let (e, beat, angle, _, edge_tol, hyst) = edge_premise(&pose);
    assert!(
        angle > 3.5 && beat > 3.0 * edge_tol && beat < hyst,
        "{beat} {angle}"
    );
    let m =
        collide_cuboids(&cube(0.5), &Pose::identity(), &cube(0.5), &pose, MARGIN).expect("overlap");
    assert_eq!((m.kind, m.len), (FeatureKind::Edge, 1));
    assert!((m.points()[0].depth - 0.001).abs() < 1e-5);
    let pair = BoxPair::new(&cube(0.5), &Pose::identity(), &cube(0.5), &pose);
    assert_eq!(
        preferred_axis(&pair, &SatQuery::new(&pair), None).axis,
        SatAxis::Edge(e)
    );
}

#[test]
fn preference_slack_is_the_hysteresis_tolerance_when_the_edge_is_face_like_for_either_face() {
    // Roll 1 degree, yaw 4: the deepest edge (A's x cross B's z) is within 1 degree of A's face
    // normal and 4 of B's, so face-like for A's face only.
    for (roll, yaw, like_a) in [(1.0, 4.0, true), (4.0, 1.0, false)] {
        let pose = resting(roll, yaw, 0.1, 0.1, 0.001);
        let (a, b) = (cube(0.5), cube(0.5));
        let pair = BoxPair::new(&a, &Pose::identity(), &b, &pose);
        let sat = SatQuery::new(&pair);
        let (x, y) = (Box64::new(&a, &Pose::identity()), Box64::new(&b, &pose));
        let spec = Spec::new(&x, &y, MARGIN as f64, 0.0);
        let (e, _, _) = best_of(&spec.sat.edge.map(|s| s.unwrap_or(f64::NEG_INFINITY)));
        let n = spec.normal(Axis::Edge(e)).expect("not parallel");
        let angle = |m: &V64| n.dot(m).abs().acos().to_degrees();
        let (to_a, to_b) = (angle(&x.axes[1]), angle(&y.axes[1]));
        assert_eq!((to_a < 3.0, to_b < 3.0), (like_a, !like_a), "{to_a} {to_b}");
        let (_, sa) = sat.best_face_a(&pair);
        let (_, sb) = sat.best_face_b(&pair);
        let want = hysteresis(sa.max(sb) as f64);
        let slack = preference_slack(&pair, &sat) as f64;
        assert!((slack - want).abs() < 1e-7, "{slack} vs {want}");
    }
    // The crossed edges 0.1 apart: the faces are all at 45 degrees to the edge axis (not face
    // like), and tie by symmetry at 1/sqrt(2) (sqrt(2) + 0.1) - 0.5 - (1 + 1/sqrt(2)) / 2 =
    // -0.282843; the face and edge tolerances are then equal, 2e-3 * 0.282843 + 2e-5 * 0.5.
    let (pose_a, pose_b) = crossed_edges(0.5, 0.1);
    let pair = BoxPair::new(&cube(0.5), &pose_a, &cube(0.5), &pose_b);
    let slack = preference_slack(&pair, &SatQuery::new(&pair));
    assert!((slack - 5.756_86e-4).abs() < 1e-8, "{slack}");
}
