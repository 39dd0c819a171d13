//! Contact recycling: a reused manifold against a fresh one, and the three tests that refuse
//! one.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Cuboid, Manifold, Pose, Real, Rot, Vec3};
use tumble_narrow::collide_cuboids;

use crate::{
    CachedManifold, Contact, ContactCache, DEFAULT_RECYCLE_DISTANCE, RECYCLE_NORMAL_COS,
    recycle_tolerance,
};

const MARGIN: Real = 0.02;

/// A 2 x 1 x 2 m slab A and a unit cube B resting on it, 5 mm deep, turned about the vertical
/// by `yaw` and moved `offset` across the slab.
fn resting(yaw: Real, offset: Vec3) -> (Cuboid, Pose, Cuboid, Pose) {
    let a = Cuboid::new(Vec3::new(1.0, 0.5, 1.0));
    let b = Cuboid::new(Vec3::repeat(0.5));
    let pose_a = Pose::translation(0.3, -0.5, -0.2);
    let mut pose_b = Pose::translation(0.3 + offset.x, 0.495 + offset.y, -0.2 + offset.z);
    pose_b.rotation = Rot::from_axis_angle(&Vec3::y_axis(), yaw);
    (a, pose_a, b, pose_b)
}

/// `pose` moved by `shift` and turned by `angle` about `axis` (through its centre).
fn moved(pose: &Pose, shift: Vec3, axis: Vec3, angle: Real) -> Pose {
    let mut out = *pose;
    out.translation.vector += shift;
    out.rotation = Rot::from_scaled_axis(axis.normalize() * angle) * out.rotation;
    out
}

/// The cache entry of the fresh manifold of `a` at `pose_a` and `b` at `pose_b`.
fn entry(a: &Cuboid, pose_a: &Pose, b: &Cuboid, pose_b: &Pose) -> (Manifold, CachedManifold) {
    let m = collide_cuboids(a, pose_a, b, pose_b, MARGIN).expect("the boxes touch");
    (
        m,
        CachedManifold::of(&Contact::new(0, 1, m), pose_a, pose_b),
    )
}

/// [`resting`] at a random yaw (up to 0.6 rad) and offset (up to 0.3 m along each
/// horizontal axis).
fn resting_anywhere(rng: &mut ChaCha8Rng) -> (Cuboid, Pose, Cuboid, Pose) {
    let yaw = rng.random_range(-0.6..0.6);
    let offset = Vec3::new(
        rng.random_range(-0.3..0.3),
        0.0,
        rng.random_range(-0.3..0.3),
    );
    resting(yaw, offset)
}

fn random_unit(rng: &mut ChaCha8Rng) -> Vec3 {
    loop {
        let v = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let n = v.norm();
        if n > 0.1 && n <= 1.0 {
            return v / n;
        }
    }
}

#[test]
fn a_recycled_manifold_stays_within_its_tolerance_of_a_fresh_one() {
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    let (mut reused, mut refused) = (0, 0);
    let (mut worst_depth, mut worst_position, mut worst_normal): (Real, Real, Real) =
        (0.0, 0.0, 0.0);
    // Both boxes are at least 0.5 m: the full distance.
    let tolerance = DEFAULT_RECYCLE_DISTANCE;
    for _ in 0..4000 {
        let (a, pose_a, b, pose_b) = resting_anywhere(&mut rng);
        let (first, cached) = entry(&a, &pose_a, &b, &pose_b);
        // Motions of either body of up to 1.5 mm and 0.1 degrees (which moves the cube's
        // corners by up to 1.2 mm more): some stay within the 1 mm tolerance and are reused,
        // the rest must be refused.
        let shift = random_unit(&mut rng) * rng.random_range(0.0..0.0015);
        let angle = rng.random_range(0.0..0.1_f32.to_radians());
        let (pose_a2, pose_b2) = if rng.random_bool(0.5) {
            (pose_a, moved(&pose_b, shift, random_unit(&mut rng), angle))
        } else {
            (moved(&pose_a, shift, random_unit(&mut rng), angle), pose_b)
        };
        assert_eq!(
            recycle_tolerance(DEFAULT_RECYCLE_DISTANCE, &a, &b),
            tolerance
        );
        let Some(recycled) = cached.recycle(&pose_a2, &pose_b2, MARGIN, tolerance) else {
            refused += 1;
            continue;
        };
        reused += 1;
        let fresh = collide_cuboids(&a, &pose_a2, &b, &pose_b2, MARGIN).expect("still touching");
        // The same points: the cube's face stays within the slab's, so a fresh clipping
        // keeps its four corners under the same ids.
        assert_eq!(recycled.len, fresh.len);
        assert_eq!(
            (recycled.kind, recycled.feature),
            (first.kind, first.feature)
        );
        worst_normal = worst_normal.max(recycled.normal.dot(&fresh.normal).min(1.0).acos());
        for p in recycled.points() {
            let q = fresh
                .points()
                .iter()
                .find(|q| q.id == p.id)
                .expect("every recycled id is in the fresh manifold");
            worst_depth = worst_depth.max((p.depth - q.depth).abs());
            worst_position = worst_position.max((p.position - q.position).norm());
        }
    }
    println!(
        "{reused} reused, {refused} refused; worst normal {worst_normal} rad, depth {worst_depth} m, position {worst_position} m"
    );
    assert!(
        reused > 1000 && refused > 1000,
        "{reused} reused, {refused} refused"
    );
    // The normal: the fresh one is the reference face's, the recycled one A's cached normal
    // carried by A; the two differ by at most the relative turn that the test allows.
    assert!(
        worst_normal <= RECYCLE_NORMAL_COS.acos() + 1e-4,
        "normal off by {worst_normal} rad"
    );
    // A point's depth: exact for its two anchors, which are the fresh point's own features
    // (the cube's corner and the slab's face). What differs is the direction it is measured
    // along (at most the 1 degree turn: a 5 mm depth changes by 5e-3 * (1 - cos 1 degree),
    // nothing) and the f32 round-off of poses a metre from the origin (6e-8 m a step); 2e-6 m is
    // 0.04% of the 5 mm depth.
    assert!(worst_depth <= 2e-6, "depth off by {worst_depth} m");
    // A point's position: midway between its anchors, which slid apart by at most the
    // tolerance across the normal, where the fresh point is midway along the normal; half the
    // tolerance plus the same round-off.
    assert!(
        worst_position <= 0.5 * tolerance + 2e-5,
        "position off by {worst_position} m"
    );
}

#[test]
fn each_test_refuses_a_manifold() {
    let (a, pose_a, b, pose_b) = resting(0.2, Vec3::new(0.1, 0.0, -0.05));
    let (_, cached) = entry(&a, &pose_a, &b, &pose_b);
    let tolerance = recycle_tolerance(DEFAULT_RECYCLE_DISTANCE, &a, &b);
    let recycle = |pose_b: &Pose| cached.recycle(&pose_a, pose_b, MARGIN, tolerance);
    // Unmoved: reused with the same depths.
    let same = recycle(&pose_b).expect("unmoved");
    assert!(same.points().iter().all(|p| (p.depth - 0.005).abs() < 1e-5));
    // Slid 0.9 mm: reused; 1.1 mm: refused.
    let slide = |d: Real| moved(&pose_b, Vec3::new(d, 0.0, 0.0), Vec3::y(), 0.0);
    assert!(recycle(&slide(0.0009)).is_some());
    assert!(recycle(&slide(0.0011)).is_none());
    // The normal test alone: the cached normal in B's frame turned against A's by 0.8
    // degrees is reused, by 1.2 degrees refused (the poses unmoved, so no point moved).
    for (deg, reused) in [(0.8, true), (1.2, false)] {
        let mut turned = cached;
        turned.normal_b =
            Rot::from_axis_angle(&Vec3::x_axis(), Real::to_radians(deg)) * turned.normal_b;
        let found = turned.recycle(&pose_a, &pose_b, MARGIN, tolerance);
        assert_eq!(found.is_some(), reused, "normal turned {deg} degrees");
    }
    // Lifted 6 mm: the overlapping points (5 mm deep) are now apart.
    let lift = |d: Real| moved(&pose_b, Vec3::new(0.0, d, 0.0), Vec3::y(), 0.0);
    assert!(recycle(&lift(0.004)).is_some());
    assert!(recycle(&lift(0.006)).is_none());
    // A millimetre cube gets a hundredth of its half extent, 5 micrometres.
    let tiny = Cuboid::new(Vec3::repeat(5e-4));
    let small = recycle_tolerance(DEFAULT_RECYCLE_DISTANCE, &a, &tiny);
    assert!((small - 5e-6).abs() < 1e-12, "{small}");
    // Recycling off: nothing is reused.
    assert!(cached.recycle(&pose_a, &pose_b, MARGIN, 0.0).is_none());
}

#[test]
fn a_slow_slide_adds_up_to_a_fresh_manifold() {
    // B slides 0.6 mm a step across A. Each step's slide is within the 1 mm tolerance, but
    // the anchors stay those of the manifold last computed, so the second step's 1.2 mm is
    // refused: a pile that creeps still gets fresh manifolds.
    let (a, pose_a, b, pose_b) = resting(0.0, Vec3::zeros());
    let bodies = |pose_b: Pose| {
        let mut out =
            [crate::tests::cube(crate::BodyKind::Fixed, pose_a, crate::Material::default()); 2];
        out[0].shape = a;
        out[1].shape = b;
        out[1].pose = pose_b;
        out
    };
    let key = (1, 2);
    let mut cache = ContactCache::new();
    let (m, _) = entry(&a, &pose_a, &b, &pose_b);
    cache.store(&[key], &[Contact::new(0, 1, m)], &bodies(pose_b));
    let tolerance = recycle_tolerance(DEFAULT_RECYCLE_DISTANCE, &a, &b);
    let step = |k: Real| moved(&pose_b, Vec3::new(0.0006 * k, 0.0, 0.0), Vec3::y(), 0.0);
    let once = cache
        .get(&key)
        .unwrap()
        .recycle(&pose_a, &step(1.0), MARGIN, tolerance)
        .expect("0.6 mm is within the tolerance");
    let contact = Contact {
        recycled: true,
        ..Contact::new(0, 1, once)
    };
    cache.store(&[key], &[contact], &bodies(step(1.0)));
    assert!(
        cache
            .get(&key)
            .unwrap()
            .recycle(&pose_a, &step(2.0), MARGIN, tolerance)
            .is_none(),
        "1.2 mm since the manifold was computed"
    );
    // The same contact stored as fresh takes new anchors, and the next 0.6 mm is reused.
    cache.store(&[key], &[Contact::new(0, 1, once)], &bodies(step(1.0)));
    assert!(
        cache
            .get(&key)
            .unwrap()
            .recycle(&pose_a, &step(2.0), MARGIN, tolerance)
            .is_some()
    );
}

/// The cache's entry for a recycled contact (`CachedManifold::recycled_of`, which skips the
/// anchors) is bit for bit the entry computed in full with the old anchors put back
/// (`of(..).with_anchors_of(last)`): the shortcut may change no bit of the next step's
/// recycling or warm start.
#[test]
fn a_recycled_entry_is_the_full_entry_with_the_old_anchors() {
    let mut rng = ChaCha8Rng::seed_from_u64(43);
    let mut checked = 0;
    for _ in 0..2000 {
        let (a, pose_a, b, pose_b) = resting_anywhere(&mut rng);
        let (_, last) = entry(&a, &pose_a, &b, &pose_b);
        let shift = random_unit(&mut rng) * rng.random_range(0.0..0.0008);
        let pose_b2 = moved(&pose_b, shift, random_unit(&mut rng), 0.0);
        let Some(m) = last.recycle(&pose_a, &pose_b2, MARGIN, DEFAULT_RECYCLE_DISTANCE) else {
            continue;
        };
        let mut c = Contact::new(0, 1, m);
        c.recycled = true;
        for (k, p) in c.impulses.iter_mut().enumerate() {
            p.normal = rng.random_range(0.0..10.0) + k as Real;
        }
        c.tilt_impulse = random_unit(&mut rng);
        let full = CachedManifold::of(&c, &pose_a, &pose_b2).with_anchors_of(&last);
        let short = CachedManifold::recycled_of(&c, &pose_a, &last);
        // Debug output of f32 fields prints every bit that differs (shortest round-trip).
        assert_eq!(format!("{short:?}"), format!("{full:?}"));
        checked += 1;
    }
    // Shifts of at most 0.8 mm stay within the 1 mm tolerance: nearly every case is reused.
    assert!(checked > 1500, "only {checked} recycled");
}
