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

#[test]
fn a_large_boxs_vertex_near_a_small_box_gives_a_unit_normal() {
    // The third fuzz run's finding, at its worst inside the supported range: the vertex
    // contact's normal was (point_b - point_a) / distance with point_b = vertex + gap, and
    // adding a 1 cm gap to a coordinate near 1000 m drops the gap's low digits (f32 steps of
    // 6e-5 m there), so the difference was up to about 0.5% shorter or longer than the gap it
    // divides. A 1000 m box's corner 1 cm from a small rotated box, over seeded directions and
    // rotations: every normal is unit within 2e-6 (a few ulp of the division and the rotation;
    // the narrow phase's tests allow 1e-5), and some of these contacts are A's vertex
    // contacts, the case the cancellation hit.
    let a = cube(1000.0);
    let b = Cuboid::new(Vec3::new(0.5, 0.3, 0.2));
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut unit = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 40) as Real / (1u64 << 24) as Real
    };
    let (mut vertex_of_a, mut worst) = (0, 0.0 as Real);
    for _ in 0..2000 {
        let rot = Rot::new_normalize(tumble_geometry::nalgebra::Quaternion::new(
            unit() - 0.5,
            unit() - 0.5,
            unit() - 0.5,
            unit() - 0.5,
        ));
        // Out of A's corner (1000, 1000, 1000), into its octant.
        let dir = Vec3::new(0.2 + unit(), 0.2 + unit(), 0.2 + unit()).normalize();
        // B's point nearest A's corner sits 1 cm away along dir: B's support in -dir.
        let support = (rot
            * b.half_extents
                .component_mul(&(rot.inverse() * -dir).map(Real::signum)))
        .dot(&-dir);
        let centre = Vec3::repeat(1000.0) + dir * (0.01 + support);
        let pose_b = at(centre.x, centre.y, centre.z, rot);
        let Some(m) = collide_cuboids(&a, &Pose::identity(), &b, &pose_b, MARGIN) else {
            continue;
        };
        if m.feature >= VERTEX_OF_A_FEATURE {
            vertex_of_a += 1;
        }
        worst = worst.max((m.normal.norm() - 1.0).abs());
    }
    assert!(
        vertex_of_a >= 5,
        "only {vertex_of_a} of A's vertex contacts"
    );
    assert!(worst <= 2e-6, "a normal is {worst} off unit length");
}
