//! SAT queries and exact ties.

use super::*;

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
    let (pose_a, pose_b) = crossed_edges(0.5, 0.1);
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
