//! Inputs the `collide_cuboids` fuzz target (fuzz/fuzz_targets/collide_cuboids.rs) found, kept as
//! regression tests with what the narrow phase promises for them.

use super::*;
use crate::SUPPORTED_LENGTH;
use tumble_geometry::{MAX_MANIFOLD_POINTS, nalgebra::Quaternion};

/// A rotation from `[x, y, z, w]`, normalized as the fuzz target does (in f64, then in f32).
fn rotation(q: [f64; 4]) -> Rot {
    let [x, y, z, w] = q;
    let n = (x * x + y * y + z * z + w * w).sqrt();
    Rot::new_normalize(Quaternion::new(w / n, x / n, y / n, z / n).cast::<f32>())
}

/// One to four finite points and a finite normal: what holds at any length.
fn assert_shape(m: &Manifold) {
    assert!(
        (1..=MAX_MANIFOLD_POINTS).contains(&(m.len as usize)),
        "{m:?}"
    );
    assert!(m.normal.iter().all(|c| c.is_finite()), "{m:?}");
    assert!(
        m.points()
            .iter()
            .all(|p| p.position.iter().all(|c| c.is_finite()) && p.depth.is_finite()),
        "{m:?}"
    );
}

#[test]
fn a_needle_of_1e28_m_against_a_5e27_m_box_keeps_the_shape_of_its_manifold() {
    // The first input the fuzz target stopped on: box A is 4e-30 by 4e-31 by 2.5e28 m (an
    // aspect ratio of 1e58), B is 5e27 m long, and the margin is 341 m. Its edge contact's point
    // lay 2e27 m from A, against a tolerance of 1e-3 of the larger box (2.5e25 m): the edge
    // closest points divide products of squared lengths, which are far outside f32 there. So
    // the narrow phase documents the lengths it is specified for (`SUPPORTED_LENGTH`) and, as
    // here, promises only the manifold's shape outside them.
    let p100 = 2f32.powi(-100);
    let a = Cuboid::new(Vec3::new(5.0 * p100, 0.5 * p100, 5.0 * 2f32.powi(92)));
    let b = Cuboid::new(Vec3::new(
        8362.0 / 64.0 * 2f32.powi(85),
        21845.0 / 64.0,
        21845.0 / 64.0,
    ));
    let pose_a = Pose::from_parts(
        Translation3::new(21845.0 / 64.0, 0.0, 3.343811),
        rotation([0.0, 1.466_033_5e13, 0.0, 0.0]),
    );
    let pose_b = Pose::from_parts(
        Translation3::new(8277.0 / 64.0, 16469.0 / 64.0, 85.0 / 64.0),
        rotation([
            1.084_202_2e-19,
            16469.0 / 64.0,
            21845.0 / 64.0,
            21845.0 / 64.0,
        ]),
    );
    let margin = 21845.0 / 64.0;
    assert!(
        a.half_extents.max() > SUPPORTED_LENGTH.1 && a.half_extents.min() < SUPPORTED_LENGTH.0,
        "the case lies outside the supported range on both ends"
    );
    let fresh = collide_cuboids(&a, &pose_a, &b, &pose_b, margin).expect("the boxes overlap");
    assert_shape(&fresh);
    let cached = collide_cuboids_cached(
        &a,
        &pose_a,
        &b,
        &pose_b,
        margin,
        Some((FeatureKind::FaceB, 0)),
    )
    .expect("the boxes overlap");
    assert_shape(&cached);
}
