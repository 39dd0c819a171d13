//! What the random pairs cannot pin down: exact ties and their documented winners, the
//! hysteresis and preference thresholds on configurations built to sit clearly on one side,
//! the id and feature packing on hand-derived contacts, the tolerance values, the frame
//! mapping of `BoxPair`, vertex contacts of separated corners, and the margin cutoff.

mod axes;
mod fuzzed;
mod ids;
mod margin;
mod preferences;

use super::reference::{Box64, V64, best_of};
use super::spec::{Axis, Spec};
use super::{MARGIN, aligned_pair, at, crossed_edges, cube, cube_on_slab};
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
