//! Inputs the `collide_cuboids` fuzz target (fuzz/fuzz_targets/collide_cuboids.rs) found, kept as
//! regression tests with what the narrow phase promises for them.

use super::*;
use crate::{SUPPORTED_ASPECT, SUPPORTED_LENGTH};
use tumble_geometry::{
    MAX_MANIFOLD_POINTS,
    nalgebra::{Isometry3, Quaternion, Vector3},
};

/// A rotation from `[x, y, z, w]`, normalized as the fuzz target does (in f64, then in f32).
fn rotation(q: [f64; 4]) -> Rot {
    let [x, y, z, w] = q;
    let n = (x * x + y * y + z * z + w * w).sqrt();
    Rot::new_normalize(Quaternion::new(w / n, x / n, y / n, z / n).cast::<f32>())
}

/// A seeded stream of numbers uniform in `[0, 1)`, 24 bits each: the top bits of a 64-bit
/// linear congruential generator (Knuth's MMIX constants), so the cases need no RNG crate and
/// stay the same on every platform.
fn uniform(seed: u64) -> impl FnMut() -> Real {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 40) as Real / (1u64 << 24) as Real
    }
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
    let mut unit = uniform(0x9e37_79b9_7f4a_7c15);
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

/// Distance from world point `p` to box `c` at `pose`, in f64 (as the fuzz target measures it).
fn distance_to_box(c: &Cuboid, pose: &Pose, p: &Point3) -> f64 {
    let pose: Isometry3<f64> = pose.cast();
    let local = pose.inverse_transform_point(&p.cast::<f64>());
    let h: Vector3<f64> = c.half_extents.cast();
    (local.coords - local.coords.zip_map(&h, |x, h| x.clamp(-h, h))).norm()
}

/// How far the manifold's worst point lies beyond `|depth|` from either box, over the fuzz
/// target's tolerance (1e-3 of the larger box plus 1e-6 of the translations): above 1 fails the
/// target's check. A point of depth `d` is the midpoint of a surface point of each box along the
/// normal, so it lies within `|d|` of each box.
fn excess_over_tolerance(m: &Manifold, a: &Cuboid, pa: &Pose, b: &Cuboid, pb: &Pose) -> f64 {
    let noise = f64::from(a.half_extents.max().max(b.half_extents.max()));
    let far = f64::from(pa.translation.vector.norm() + pb.translation.vector.norm());
    let tol = 1e-3 * noise + 1e-6 * far;
    let mut worst = f64::NEG_INFINITY;
    for p in m.points() {
        for (c, pose) in [(a, pa), (b, pb)] {
            let excess = distance_to_box(c, pose, &p.position) - f64::from(p.depth).abs();
            worst = worst.max(excess / tol);
        }
    }
    worst
}

/// Finding 5's configuration, drawn at random: box A's thinnest half extent is `ratio` of the
/// pair's largest (world-bounds sizes: the large box up to 1000 m, A 100 to 1000 m long); A lies
/// across a face of the large box B with its thin axis along that face, so that A's thin side
/// planes cut B's face (the clipping the finding lost); turned about that axis by a multiple of
/// 90 degrees plus up to 0.6 degrees (the finding had 0.35: A's and B's face axes nearly tie);
/// its centre on B's face, near the face's middle line. Half of the pairs are turned as a whole.
fn thin_box_across_a_face(
    ratio: Real,
    unit: &mut impl FnMut() -> Real,
) -> (Cuboid, Pose, Cuboid, Pose) {
    use std::f32::consts::FRAC_PI_2;
    fn sym(unit: &mut impl FnMut() -> Real) -> Real {
        2.0 * unit() - 1.0
    }
    let hb = if sym(unit) < 0.0 {
        Vec3::repeat(1000.0)
    } else {
        Vec3::new(0.3 + 0.7 * unit(), 0.3 + 0.7 * unit(), 0.3 + 0.7 * unit()) * 1000.0
    };
    let long = 1000.0 * (0.1 + 0.9 * unit());
    let thin = ratio * long.max(hb.max());
    let mid = thin * (100.0 / thin).powf(unit());
    let a = Cuboid::new(Vec3::new(mid, thin, long));
    let b = Cuboid::new(hb);
    // B: one of the exact half turns, so its y axis stays exactly along A's thin axis.
    let half_turn = [
        Quaternion::new(1.0, 0.0, 0.0, 0.0),
        Quaternion::new(0.0, 1.0, 0.0, 0.0),
        Quaternion::new(0.0, 0.0, 1.0, 0.0),
        Quaternion::new(0.0, 0.0, 0.0, 1.0),
    ][(unit() * 4.0) as usize];
    let mut rot_b = Rot::new_normalize(half_turn);
    let angle = (unit() * 4.0).floor() * FRAC_PI_2 + sym(unit) * 0.01;
    let mut rot_a = Rot::from_axis_angle(&Vec3::y_axis(), angle);
    // A's centre in B's frame: on the x or z face, within 1% of B's height of its middle, and
    // in or out of it by up to A's half size.
    let mut c = Vec3::new(sym(unit) * hb.x, sym(unit) * hb.y * 0.01, sym(unit) * hb.z);
    let axis = if unit() < 0.5 { 0 } else { 2 };
    c[axis] = hb[axis].copysign(sym(unit)) + sym(unit) * (mid + long) * 0.5;
    let mut offset = rot_b * c;
    if unit() < 0.5 {
        let turn = Rot::new_normalize(Quaternion::new(sym(unit), sym(unit), sym(unit), sym(unit)));
        (rot_a, rot_b, offset) = (turn * rot_a, turn * rot_b, turn * offset);
    }
    let centre_b = Vec3::new(sym(unit), sym(unit), sym(unit)) * 100.0;
    let centre_a = centre_b + offset;
    (
        a,
        at(centre_a.x, centre_a.y, centre_a.z, rot_a),
        b,
        at(centre_b.x, centre_b.y, centre_b.z, rot_b),
    )
}

#[test]
fn a_slab_thinner_than_the_supported_aspect_keeps_the_shape_of_its_manifold() {
    // The fifth finding: box A is 198 by 0.05 by 13,323,083 m (half extents), its centre on the
    // face of a cube of half extent 13,323,083 m, turned 179.65 degrees about its thin axis,
    // which lies exactly along the cube's y axis; margin 1.0625 m. Every length is within
    // `SUPPORTED_LENGTH`, but A's thin side (0.05 m) is 4e-9 of the cube, while one f32 step of
    // the cube's coordinates is 1 m: A's face contact clipped to no points, the fallback edge
    // axis was the cube's face normal, and the support edge it picked put the point 6.7e6 m
    // from A. So the narrow phase documents the thinness it is specified for
    // (`SUPPORTED_ASPECT`) and, as here, promises only the manifold's shape below it.
    let a = Cuboid::new(Vec3::new(198.0, 0.05, 13_323_083.0));
    let b = cube(13_323_083.0);
    let pose_a = at(
        13_323_083.0,
        0.05,
        0.01,
        rotation([0.0, 340.0, 0.0, f64::from(1.04f32)]),
    );
    let pose_b = at(1.0, 71.0 / 64.0, 0.0, rotation([1.0 / 64.0, 0.0, 0.0, 0.0]));
    let margin = 68.0 / 64.0;
    let (lo, hi) = SUPPORTED_LENGTH;
    assert!(
        [a.half_extents, b.half_extents]
            .iter()
            .all(|h| h.iter().all(|&c| (lo..=hi).contains(&c))),
        "every length is within the supported range"
    );
    assert!(
        a.half_extents.min() < SUPPORTED_ASPECT * b.half_extents.max(),
        "A is thinner than the supported aspect"
    );
    let fresh = collide_cuboids(&a, &pose_a, &b, &pose_b, margin).expect("the boxes overlap");
    assert_shape(&fresh);
    assert_eq!(
        Some(fresh),
        collide_cuboids(&a, &pose_a, &b, &pose_b, margin),
        "two calls agree"
    );
    for previous in [
        (FeatureKind::FaceA, 0),
        (FeatureKind::FaceB, 0),
        (FeatureKind::Edge, 71),
    ] {
        let cached = collide_cuboids_cached(&a, &pose_a, &b, &pose_b, margin, Some(previous))
            .expect("the boxes overlap");
        assert_shape(&cached);
    }
}

#[test]
fn thin_boxes_at_the_supported_aspect_keep_their_points_on_both_boxes() {
    // Finding 5's configuration (`thin_box_across_a_face`) over 20,000 seeded pairs with A's
    // thinnest half extent exactly `SUPPORTED_ASPECT` of the pair's largest: 1 mm against
    // 1000 m at the most, the world's own extreme. Every point must lie within `|depth|` of
    // both boxes, up to the fuzz target's tolerance (1e-3 of the larger box, 1 m here: f32
    // rounding amplified by up to 1e3 at the parallel-edge cutoff); the finding's point was
    // half the large box off, 500 times that tolerance. (15,248 of the pairs touch; none fails.)
    let mut unit = uniform(0x5eed_0005);
    let mut run = |ratio: Real| {
        let (mut contacts, mut failed, mut worst) = (0, 0, f64::NEG_INFINITY);
        for _ in 0..20_000 {
            let (a, pa, b, pb) = thin_box_across_a_face(ratio, &mut unit);
            let margin = unit();
            let Some(m) = collide_cuboids(&a, &pa, &b, &pb, margin) else {
                continue;
            };
            contacts += 1;
            let excess = excess_over_tolerance(&m, &a, &pa, &b, &pb);
            failed += usize::from(excess > 1.0);
            worst = worst.max(excess);
        }
        (contacts, failed, worst)
    };
    let (contacts, failed, worst) = run(SUPPORTED_ASPECT);
    assert!(contacts >= 10_000, "only {contacts} of the pairs touch");
    assert_eq!(
        failed, 0,
        "{failed} manifolds off their boxes (worst {worst} tolerances)"
    );
    // The same poses 100 times thinner, below the supported aspect: some do lose their
    // contact (13 of 14,943, up to 470 tolerances off), so the pairs above reach the failure's
    // configuration. Should none fail here any
    // more, the narrow phase handles thinner boxes and `SUPPORTED_ASPECT` can be lowered.
    let (contacts, failed, worst) = run(SUPPORTED_ASPECT * 1e-2);
    assert!(
        failed > 0,
        "no failure among {contacts} contacts below the supported aspect (worst {worst})"
    );
}
