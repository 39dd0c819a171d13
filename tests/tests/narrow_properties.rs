//! Properties of the box-box narrow phase over random poses and sizes: finite output, a unit
//! normal, at most four points, depths bounded by what two boxes can overlap, a contact whenever
//! a centre is inside the other box, and a history that never breaks the manifold.
//!
//! The properties hold for every manifold, so each test also counts how many cases produced one
//! (and reached each branch) and bounds those counts: a narrow phase that returned nothing would
//! otherwise pass.
//!
//! Runtime: about a second.

use proptest::prelude::*;
use proptest::test_runner::{TestCaseResult, TestRunner};
use std::cell::Cell;
use tumble_geometry::{
    Cuboid, FeatureKind, MAX_MANIFOLD_POINTS, Point3, Pose, Real, Rot, Vec3,
    nalgebra::{Quaternion, Translation3},
};
use tumble_narrow::{collide_cuboids, collide_cuboids_cached};

/// Cases per property: enough to reach edge-edge, vertex and deep contacts many times over.
const CASES: u32 = 16_384;

/// A fixed seed, so that CI sees the same cases on every run and a failure reproduces.
const SEED: u64 = 0x7475_6d62_6c65;

/// A uniform `f32` in `[lo, hi)`, sampled in `f64` and rounded: proptest's own `f32` range
/// sampler can trip an internal assertion on some seeds.
fn uniform(lo: f64, hi: f64) -> impl Strategy<Value = f32> {
    (lo..hi).prop_map(|v| v as f32)
}

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: CASES,
        rng_seed: proptest::test_runner::RngSeed::Fixed(SEED),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

fn half_extents() -> impl Strategy<Value = Vec3> {
    (
        uniform(0.01, 10.0),
        uniform(0.01, 10.0),
        uniform(0.01, 10.0),
    )
        .prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn rotation() -> impl Strategy<Value = Rot> {
    // Any non-zero quaternion, normalised: every orientation is reachable.
    (
        uniform(-1.0, 1.0),
        uniform(-1.0, 1.0),
        uniform(-1.0, 1.0),
        uniform(-1.0, 1.0),
    )
        .prop_filter("a quaternion needs a direction", |(w, x, y, z)| {
            w * w + x * x + y * y + z * z > 1e-3
        })
        .prop_map(|(w, x, y, z)| Rot::from_quaternion(Quaternion::new(w, x, y, z)))
}

/// Two boxes whose centres are at most 0.6 times the sum of their circumradii apart along each
/// axis: overlapping (about 60 % of the cases), touching, within the margin and apart all occur.
fn box_pair() -> impl Strategy<Value = (Cuboid, Pose, Cuboid, Pose)> {
    (
        half_extents(),
        half_extents(),
        rotation(),
        rotation(),
        (uniform(-0.6, 0.6), uniform(-0.6, 0.6), uniform(-0.6, 0.6)),
        uniform(-5.0, 5.0),
    )
        .prop_map(|(ha, hb, ra, rb, (x, y, z), base)| {
            let reach = ha.norm() + hb.norm();
            let pose_a = Pose::from_parts(Translation3::new(base, -base, 0.5 * base), ra);
            let pose_b = Pose::from_parts(
                Translation3::from(pose_a.translation.vector + Vec3::new(x, y, z) * reach),
                rb,
            );
            (Cuboid::new(ha), pose_a, Cuboid::new(hb), pose_b)
        })
}

/// Runs `test` on `CASES` cases of `strategy` with the fixed configuration, panicking with
/// proptest's (shrunk) counterexample on failure.
fn run_cases<S: Strategy>(strategy: S, test: impl Fn(S::Value) -> TestCaseResult) {
    let mut runner = TestRunner::new(config());
    if let Err(e) = runner.run(&strategy, test) {
        panic!("{e}");
    }
}

/// Adds one to a counter the test closure (an `Fn`) shares with its caller.
fn bump(counter: &Cell<usize>, by: usize) {
    counter.set(counter.get() + by);
}

/// Whether `pose_b`'s centre is inside (or on) box `a` at `pose_a`: the boxes then overlap by at
/// least the smaller half extent of B (0.01 here), far beyond any rounding, so they must touch.
fn centre_inside(a: &Cuboid, pose_a: &Pose, pose_b: &Pose) -> bool {
    let c = pose_a.inverse_transform_point(&Point3::from(pose_b.translation.vector));
    (0..3).all(|k| c[k].abs() <= a.half_extents[k])
}

#[test]
fn manifolds_are_finite_unit_small_and_bounded() {
    let [cases, contacts, multi, apart, speculative, edges, inside] =
        std::array::from_fn(|_| Cell::new(0));
    run_cases(
        (box_pair(), uniform(0.0, 0.1)),
        |((a, pa, b, pb), margin)| {
            bump(&cases, 1);
            let manifold = collide_cuboids(&a, &pa, &b, &pb, margin);
            // A centre inside the other box is a deep overlap: there must be a manifold.
            if centre_inside(&a, &pa, &pb) || centre_inside(&b, &pb, &pa) {
                bump(&inside, 1);
                prop_assert!(
                    manifold.is_some(),
                    "a centre inside the other box, no contact"
                );
            }
            let Some(m) = manifold else {
                return Ok(());
            };
            bump(&contacts, 1);
            bump(&multi, usize::from(m.len >= 2));
            bump(&apart, m.points().iter().filter(|p| p.depth < 0.0).count());
            bump(&speculative, usize::from(m.max_depth() < 0.0));
            bump(&edges, usize::from(m.kind == FeatureKind::Edge));
            prop_assert!(m.normal.iter().all(|c| c.is_finite()));
            // A unit normal: f32 normalisation and one rotation leave a few ulps.
            prop_assert!(
                (m.normal.norm() - 1.0).abs() <= 1e-5,
                "|n| = {}",
                m.normal.norm()
            );
            prop_assert!(m.len >= 1 && m.len as usize <= MAX_MANIFOLD_POINTS);
            // Two boxes cannot overlap by more than the sum of their circumradii (the distance
            // that separates their bounding spheres), which is below the sum of the half extents.
            let reach: Real = a.half_extents.norm() + b.half_extents.norm();
            for (i, p) in m.points().iter().enumerate() {
                prop_assert!(p.position.iter().all(|c| c.is_finite()) && p.depth.is_finite());
                prop_assert!(p.depth <= reach, "depth {} above {reach}", p.depth);
                // Kept points are within the margin (rounding of the clip: 1e-5 of the size).
                prop_assert!(
                    p.depth >= -margin - 1e-5 * reach,
                    "depth {} below -margin",
                    p.depth
                );
                // Ids name distinct features within one manifold.
                prop_assert!(m.points()[..i].iter().all(|q| q.id != p.id));
            }
            Ok(())
        },
    );
    let [cases, contacts, multi, apart, speculative, edges, inside] =
        [cases, contacts, multi, apart, speculative, edges, inside].map(|c| c.get());
    println!(
        "cases {cases}: contacts {contacts} ({edges} edge or vertex, {multi} of several points, \
         {apart} points apart, {speculative} manifolds wholly apart), a centre inside the other \
         box {inside}"
    );
    // Every check above runs only on a manifold, so a narrow phase returning `None` would pass
    // them all: count what was checked. Measured on this seed: 10,126 contacts of 16,384 cases
    // (62 %: the centres are within 0.6 of the circumradii's sum along each axis), 4,906 of them
    // edge or vertex contacts, 4,562 with several points (what the distinct-id check needs), 217
    // points apart within the margin (what the lower depth bound needs), 87 of the manifolds
    // wholly apart (the speculative contacts the margin exists for), 1,943 cases with a
    // centre inside the other box. Each bound is about half of that, and far above zero.
    assert!(cases >= CASES as usize);
    let share = |count: usize| count as f64 / cases as f64;
    assert!(
        share(contacts) >= 0.45,
        "{contacts} contacts in {cases} cases"
    );
    assert!(
        edges >= 2_000 && contacts - edges >= 2_000,
        "{edges} edge or vertex contacts of {contacts}"
    );
    assert!(multi >= 2_500, "{multi} manifolds of several points");
    assert!(apart >= 100, "{apart} points apart within the margin");
    assert!(speculative >= 40, "{speculative} manifolds wholly apart");
    assert!(
        inside >= 1_000,
        "{inside} cases with a centre inside the other box"
    );
}

#[test]
fn last_steps_feature_never_breaks_the_manifold() {
    let [cases, deep, cached_some, kept, changed] = std::array::from_fn(|_| Cell::new(0));
    // Mostly a face index (0..6), which the hysteresis can keep when it faces the other box;
    // now and then anything up to 200, which it must reject.
    let strategy = (
        box_pair(),
        0u32..3,
        prop_oneof![3 => 0u32..6, 1 => 0u32..200],
    );
    run_cases(strategy, |((a, pa, b, pb), kind, feature)| {
        bump(&cases, 1);
        // Any history, even one that no longer fits the pair, must give a valid manifold or none.
        let kind = [FeatureKind::FaceA, FeatureKind::FaceB, FeatureKind::Edge][kind as usize];
        let fresh = collide_cuboids(&a, &pa, &b, &pb, 0.02);
        let cached = collide_cuboids_cached(&a, &pa, &b, &pb, 0.02, Some((kind, feature)));
        // History changes which features are used, never whether the boxes touch deeply.
        if fresh.is_some_and(|m| m.max_depth() > 1e-3 * a.half_extents.max()) {
            bump(&deep, 1);
            prop_assert!(cached.is_some());
        }
        if let Some(m) = cached {
            bump(&cached_some, 1);
            bump(&kept, usize::from((m.kind, m.feature) == (kind, feature)));
            let differs = fresh.is_some_and(|f| (f.kind, f.feature) != (m.kind, m.feature));
            bump(&changed, usize::from(differs));
            prop_assert!((m.normal.norm() - 1.0).abs() <= 1e-5);
            prop_assert!(m.len >= 1 && m.len as usize <= MAX_MANIFOLD_POINTS);
        }
        Ok(())
    });
    let [cases, deep, cached_some, kept, changed] =
        [cases, deep, cached_some, kept, changed].map(|c| c.get());
    println!(
        "cases {cases}: deep {deep}, cached contacts {cached_some}, history kept {kept}, \
         different from the fresh manifold {changed}"
    );
    // Measured on this seed: 9,976 deep contacts (where the cached one must exist) and 10,043
    // cached manifolds of 16,384 cases, 322 of which have the given reference face and 90 of
    // which differ from the fresh manifold (the history really changed the features). The
    // bounds, about half of that, fail a narrow phase that returns `None` (the first two) or one
    // that ignores or always rejects the history (the last: the cached manifold would then
    // always be the fresh one).
    assert!(cases >= CASES as usize);
    let share = |count: usize| count as f64 / cases as f64;
    assert!(share(deep) >= 0.45, "{deep} deep contacts in {cases} cases");
    assert!(
        share(cached_some) >= 0.45,
        "{cached_some} cached contacts in {cases} cases"
    );
    assert!(kept >= 150, "the history was kept {kept} times");
    assert!(
        changed >= 40,
        "the history changed the manifold {changed} times"
    );
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn bad_input_returns_without_panicking(
        (a, pa, b, pb) in box_pair(),
        which in 0usize..4,
        bad in prop_oneof![Just(Real::NAN), Just(Real::INFINITY), Just(-1.0f32), Just(0.0f32)],
    ) {
        // NaN or infinite coordinates, negative or zero extents: the contract is no panic (the
        // facade validates bodies before they reach the narrow phase).
        let (mut a, mut pa, mut b) = (a, pa, b);
        match which {
            0 => a.half_extents.x = bad,
            1 => b.half_extents.z = bad,
            2 => pa.translation.vector.y = bad,
            _ => pa.rotation = Rot::new_unchecked(Quaternion::new(bad, 0.0, 0.0, 0.0)),
        }
        let _ = collide_cuboids(&a, &pa, &b, &pb, 0.02);
        let _ = collide_cuboids(&a, &pa, &b, &pb, bad);
    }
}
