//! What the random pairs cannot pin down: exact ties and their documented winners, the
//! hysteresis and preference thresholds on configurations built to sit clearly on one side,
//! the id and feature packing on hand-derived contacts, the tolerance values, the frame
//! mapping of `BoxPair`, vertex contacts of separated corners, and the margin cutoff.

use super::reference::{Box64, V64, best_of};
use super::spec::{Axis, Spec};
use crate::feature_id::{
    KIND_EDGE, KIND_FACE_A, KIND_FACE_B, KIND_VERTEX, SIDE_LABEL_BASE, edge_point_id,
    face_point_id, id_kind, vertex_point_id,
};
use crate::tolerance::{
    EDGE_ABS_TOL, EDGE_REL_TOL, FACE_B_ABS_TOL, FACE_B_REL_TOL, FACE_LIKE_EDGE_COS,
    FACE_LIKE_MAX_DEPTH, HYSTERESIS_ABS_TOL, HYSTERESIS_REL_TOL, PARALLEL_EDGE_SIN_SQ, WITNESS_TOL,
    tolerance,
};
use crate::{
    BoxPair, EDGE_PAIR_COUNT, SatAxis, SatQuery, VERTEX_OF_A_FEATURE, closest_vertex,
    collide_cuboids, collide_cuboids_cached, contact_polygon, deepest_axis, edge_axis,
    face_contact, preference_slack, preferred_axis,
};
use tumble_geometry::{
    Cuboid, FeatureKind, Manifold, Point3, Pose, Real, Rot, Vec3, nalgebra::Translation3,
};

const MARGIN: Real = 0.02;

fn cube(h: Real) -> Cuboid {
    Cuboid::new(Vec3::repeat(h))
}

fn at(x: Real, y: Real, z: Real, rot: Rot) -> Pose {
    Pose::from_parts(Translation3::new(x, y, z), rot)
}

fn kind_and_feature(m: Option<Manifold>) -> Option<(FeatureKind, u32)> {
    m.map(|m| (m.kind, m.feature))
}

// ---------------------------------------------------------------------------------------------
// Tolerances.

#[test]
fn a_tolerance_is_the_relative_part_of_the_separation_plus_the_absolute_part_of_the_scale() {
    // 0.05 * |-2| + 0.01 * 3 = 0.13; the sign of the separation does not matter; f32 rounding of
    // two products and a sum of numbers below 1: a few 1e-8.
    for s in [-2.0, 2.0] {
        assert!((tolerance(s, 0.05, 0.01, 3.0) - 0.13).abs() < 1e-7);
    }
    // At zero separation only the absolute part is left; with no absolute part, only the
    // relative one.
    assert!((tolerance(0.0, 0.05, 0.01, 3.0) - 0.03).abs() < 1e-8);
    assert!((tolerance(-4.0, 0.5, 0.0, 3.0) - 2.0).abs() < 1e-7);
}

#[test]
fn the_tolerance_constants_have_the_values_their_reasons_give() {
    // 1 mrad: sin^2 of 1e-3 rad, to 1e-6 relative.
    assert!((PARALLEL_EDGE_SIN_SQ as f64 - 1e-3f64.sin().powi(2)).abs() < 1e-12);
    // 3 degrees as a cosine, to f32 precision.
    assert!((FACE_LIKE_EDGE_COS as f64 - 3f64.to_radians().cos()).abs() < 1e-7);
    // The hysteresis covers the separation change of a 0.5 degree tilt: 1 % > sin(0.5 deg).
    assert!(HYSTERESIS_ABS_TOL as f64 > 0.5f64.to_radians().sin());
    // The witness tolerance is "about 16 f32 ulps".
    let ulps = WITNESS_TOL / Real::EPSILON;
    assert!((12.0..20.0).contains(&ulps), "{ulps}");
}

// ---------------------------------------------------------------------------------------------
// BoxPair.

#[test]
fn box_pair_scales_are_the_largest_half_extent_and_the_smaller_boxs_largest() {
    let pair = BoxPair::new(
        &Cuboid::new(Vec3::new(1.0, 2.0, 3.0)),
        &Pose::identity(),
        &Cuboid::new(Vec3::new(0.5, 0.25, 2.0)),
        &Pose::translation(5.0, 0.0, 0.0),
    );
    assert_eq!(pair.noise_scale(), 3.0);
    assert_eq!(pair.feature_scale(), 2.0);
    assert_eq!(pair.swapped().noise_scale(), 3.0);
    assert_eq!(pair.swapped().feature_scale(), 2.0);
}

#[test]
fn box_pair_maps_through_a_quarter_turn_by_hand() {
    // B at (1, 2, 3), turned a quarter about z: its local x is A's y, its local y is A's -x.
    let quarter = Rot::from_euler_angles(0.0, 0.0, std::f32::consts::FRAC_PI_2);
    let pair = BoxPair::new(
        &cube(1.0),
        &Pose::identity(),
        &cube(0.5),
        &at(1.0, 2.0, 3.0, quarter),
    );
    // f32 rounding of a quarter turn's sine and cosine: a few 1e-8, times coordinates of 3.
    let close = |p: Point3, q: Point3| (p - q).norm() < 1e-6;
    assert!((pair.offset - Vec3::new(1.0, 2.0, 3.0)).norm() < 1e-6);
    assert!(close(
        pair.b_to_a(&Point3::new(1.0, 0.0, 0.0)),
        Point3::new(1.0, 3.0, 3.0)
    ));
    assert!(close(
        pair.b_to_a(&Point3::new(0.0, 1.0, 0.0)),
        Point3::new(0.0, 2.0, 3.0)
    ));
    assert!(close(
        pair.a_to_b(&Point3::new(1.0, 3.0, 4.0)),
        Point3::new(1.0, 0.0, 1.0)
    ));
    assert!((pair.abs_rot - pair.rot.abs()).norm() == 0.0);
    // Seen from B: A's centre is at -(1, 2, 3) in A's axes, i.e. (-2, 1, -3) in B's.
    let swapped = pair.swapped();
    assert!((swapped.offset - Vec3::new(-2.0, 1.0, -3.0)).norm() < 1e-6);
    assert!((swapped.rot - pair.rot.transpose()).norm() == 0.0);
    assert!(close(
        swapped.b_to_a(&Point3::origin()),
        Point3::new(-2.0, 1.0, -3.0)
    ));
}

// ---------------------------------------------------------------------------------------------
// SAT queries and exact ties.

fn aligned_pair(offset: Vec3) -> BoxPair {
    BoxPair::new(
        &cube(1.0),
        &Pose::identity(),
        &cube(1.0),
        &Pose::translation(offset.x, offset.y, offset.z),
    )
}

#[test]
fn the_first_of_equal_axes_wins() {
    // Aligned unit cubes 2.5 apart along x and along y: gap 0.5 on both axes, exactly (sums of
    // exact binary fractions). A's faces 0 (+x) and 2 (+y) tie, B's 1 (-x) and 3 (-y) tie, and
    // the edge axes that are face normals in disguise (x cross z = -y, y cross z = x, z cross x
    // = y, z cross y = -x: 3i + j = 2, 5, 6, 7) tie with them; the first of each wins.
    let pair = aligned_pair(Vec3::new(2.5, 2.5, 0.0));
    let sat = SatQuery::new(&pair);
    assert_eq!(sat.best_face_a(&pair), (0, 0.5));
    assert_eq!(sat.best_face_b(&pair), (1, 0.5));
    assert_eq!(sat.best_edge(), (2, 0.5));
    assert_eq!(sat.max_separation(), 0.5);
    // The deepest axis: A's faces win ties over B's and over edges.
    let deepest = deepest_axis(&pair, &sat);
    assert_eq!((deepest.axis, deepest.separation), (SatAxis::FaceA(0), 0.5));
    assert_eq!(preferred_axis(&pair, &sat, None).axis, SatAxis::FaceA(0));
}

#[test]
fn facing_faces_follow_the_side_b_is_on() {
    // B on A's -x side: A's -x face (1) faces it, and B's +x face (0) faces A.
    let pair = aligned_pair(Vec3::new(-2.5, 0.3, 0.1));
    let sat = SatQuery::new(&pair);
    assert_eq!(sat.best_face_a(&pair), (1, 0.5));
    assert_eq!(sat.best_face_b(&pair), (0, 0.5));
    // B below A (-y): faces 3 of A and 2 of B; the gap 0.25 is exact.
    let pair = aligned_pair(Vec3::new(0.1, -2.25, 0.3));
    let sat = SatQuery::new(&pair);
    assert_eq!(sat.best_face_a(&pair), (3, 0.25));
    assert_eq!(sat.best_face_b(&pair), (2, 0.25));
}

/// A cube of half size 0.5 turned about a generic axis, its lowest vertex `depth` below the top
/// face of an unturned cube of the same size at the origin.
fn corner_down(depth: Real) -> Pose {
    let rot = Rot::from_euler_angles(0.3, 0.2, 0.1);
    let low = (0..8)
        .map(|v| (rot * cube(0.5).vertex(v).coords).y)
        .fold(Real::INFINITY, Real::min);
    at(0.1, 0.5 - depth - low, 0.05, rot)
}

#[test]
fn the_deepest_axis_is_the_strictly_largest_of_each_kind() {
    // A turned cube's corner 1 mm into an unturned cube's top face. The premise, exactly: the
    // unturned cube's top face is the deepest axis, ahead of every other by 1e-4 at least.
    let pose = corner_down(0.001);
    let (x, y) = (
        Box64::new(&cube(0.5), &Pose::identity()),
        Box64::new(&cube(0.5), &pose),
    );
    let spec = Spec::new(&x, &y, MARGIN as f64, 1e-4);
    assert_eq!(spec.deepest(), Ok(Axis::FaceA(2)));
    // Unturned cube first: A's face; turned cube first: B's face. Either way the separation is
    // minus the corner's depth (f32 rounding of coordinates below 1: 1e-6).
    for (pair, axis) in [
        (
            BoxPair::new(&cube(0.5), &Pose::identity(), &cube(0.5), &pose),
            SatAxis::FaceA(2),
        ),
        (
            BoxPair::new(&cube(0.5), &pose, &cube(0.5), &Pose::identity()),
            SatAxis::FaceB(2),
        ),
    ] {
        let deepest = deepest_axis(&pair, &SatQuery::new(&pair));
        assert_eq!(deepest.axis, axis);
        assert!((deepest.separation + 0.001).abs() < 1e-6, "{deepest:?}");
    }
    // An edge strictly best: two cubes turned 45 degrees about different axes, their edges
    // crossing 0.1 apart (see `crossed_edges`); every face is at 45 degrees to the gap.
    let (pose_a, pose_b) = crossed_edges(0.1);
    let pair = BoxPair::new(&cube(0.5), &pose_a, &cube(0.5), &pose_b);
    let sat = SatQuery::new(&pair);
    let deepest = deepest_axis(&pair, &sat);
    assert!(matches!(deepest.axis, SatAxis::Edge(_)), "{deepest:?}");
    assert!((deepest.separation - 0.1).abs() < 1e-5);
    assert_eq!(preferred_axis(&pair, &sat, None).axis, deepest.axis);
}

#[test]
fn edge_pairs_within_a_milliradian_of_parallel_have_no_axis() {
    // B turned about y: A's x edges and B's x edges make the turn angle, their cross product is
    // +-y with length sin(angle).
    let turned = |angle: Real, y: Real| {
        BoxPair::new(
            &cube(1.0),
            &Pose::identity(),
            &cube(1.0),
            &at(0.3, y, 0.2, Rot::from_euler_angles(0.0, angle, 0.0)),
        )
    };
    let skipped = turned(0.5e-3, 3.0);
    assert_eq!(edge_axis(&skipped, 0, 0), None);
    assert_eq!(SatQuery::new(&skipped).edge[0], Real::NEG_INFINITY);
    for y in [3.0, -3.0] {
        let pair = turned(2e-3, y);
        let n = edge_axis(&pair, 0, 0).expect("2 mrad is not parallel");
        // Unit, along y, oriented from A to B (towards the side B is on); f32 rounding of a
        // normalised cross product: a few ulps.
        assert!((n - Vec3::new(0.0, y.signum(), 0.0)).norm() < 1e-5, "{n:?}");
        // Along y the gap is 3 - 1 - 1 (B's y axis is unturned); the closed form divides the
        // f32 rounding of coordinates of 3 by the sine 2e-3: 2e-4 at most.
        assert!((SatQuery::new(&pair).edge[0] - 1.0).abs() < 1e-3);
    }
}

// ---------------------------------------------------------------------------------------------
// Preferences and hysteresis.

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
fn hysteresis(best: f64) -> f64 {
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
    let (pose_a, pose_b) = crossed_edges(0.1);
    let pair = BoxPair::new(&cube(0.5), &pose_a, &cube(0.5), &pose_b);
    let slack = preference_slack(&pair, &SatQuery::new(&pair));
    assert!((slack - 5.756_86e-4).abs() < 1e-8, "{slack}");
}

// ---------------------------------------------------------------------------------------------
// Feature ids.

/// A turned 45 degrees about z, B turned 45 degrees about x and raised so that A's top edge
/// (along z) and B's bottom edge (along x) cross `gap` apart (negative: overlapping) above the
/// origin.
fn crossed_edges(gap: Real) -> (Pose, Pose) {
    let q = std::f32::consts::FRAC_PI_4;
    (
        at(0.0, 0.0, 0.0, Rot::from_euler_angles(0.0, 0.0, q)),
        at(
            0.0,
            2f32.sqrt() + gap,
            0.0,
            Rot::from_euler_angles(q, 0.0, 0.0),
        ),
    )
}

#[test]
fn crossed_edges_pack_their_pair_into_the_feature_and_the_id() {
    // A's highest edge runs along its z with local x and y both positive: edge 4 * 2 + 1 + 2 =
    // 11 in the `CUBOID_EDGES` numbering. B's lowest runs along its x with local y negative and
    // z positive: 4 * 0 + 0 + 2 = 2. The feature is 11 * 12 + 2, the id kind 2 with A's edge in
    // bits 4-7 and B's in bits 0-3.
    for gap in [-0.01, 0.01] {
        let (pose_a, pose_b) = crossed_edges(gap);
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
    let (pose_a, pose_b) = crossed_edges(0.03);
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
    let slab = Cuboid::new(Vec3::new(5.0, 0.5, 5.0));
    let m = collide_cuboids(
        &slab,
        &Pose::identity(),
        &cube(0.5),
        &Pose::translation(1.0, 0.998, -1.0),
        MARGIN,
    )
    .expect("overlap");
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

// ---------------------------------------------------------------------------------------------
// The margin.

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
