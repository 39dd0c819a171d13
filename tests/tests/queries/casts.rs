//! Ray casts (closest hit, all hits) and box casts against parry3d.

use parry3d::query::{Ray as PRay, RayCast, ShapeCastOptions, cast_shapes};
use tumble::QueryFilter;

use super::*;

/// Scenes for the ray casts, and rays per scene: 20 x 500 = 10,000 closest-hit casts and as
/// many all-hits casts.
const RAY_SCENES: u64 = 20;
const RAYS_PER_SCENE: usize = 500;

/// How far our time of impact may be from parry's, measured as the distance between the two
/// hit points across the face that was hit (`|dtoi| |dir . n|`), m: both compute the same slab
/// entry in `f32` after slightly different changes of frame, which differ by a few ulps of
/// the coordinates of up to 10 m (1e-6 m each). Along the ray the difference grows as the ray grazes
/// the face (1 / |cos|), so it is measured across it.
const TOI_ACROSS_TOL: Real = 2e-5;

/// The same along the ray, m, for hits not grazing (`|dir . n| >= 0.1 |dir|`): ten times the
/// across tolerance at the steepest angle allowed.
const TOI_ALONG_TOL: Real = 2e-4;

/// Angle between our normal and parry's, rad, away from edges: both are a rotated basis
/// vector, whose `f32` rotations differ by a few 1e-7 rad; 1e-4 leaves room and still tells
/// any two faces of a box apart (they are pi/2 apart).
const NORMAL_TOL: Real = 1e-4;

/// Hits within this distance of a second face (an edge or a corner) are not compared on the
/// normal, m: which of two faces a ray enters by there is decided by rounding. Ten times
/// [`BAND`] is well past the rounding.
const EDGE_ZONE: Real = 1e-3;

/// Largest share of casts whose result falls inside the presence band (a graze or a
/// touch decided by rounding) or between two bodies hit at the same time: none were seen
/// in 10,000; a systematic error (a slab sign, a missed axis) would put tens of percent here.
const MAX_AMBIGUOUS_SHARE: f64 = 0.01;

/// Parry's first hit of the ray on the box `h` at `pose` grown by `grow`.
fn parry_ray(
    pose: &Pose,
    h: &Vec3,
    grow: Real,
    o: &Point3,
    d: &Vec3,
    max: Real,
) -> Option<(Real, Vec3)> {
    let ray = PRay::new(PVec::new(o.x, o.y, o.z), pvec(d));
    pcuboid(h, grow)
        .cast_ray_and_get_normal(&ppose(pose), &ray, max, true)
        .map(|hit| (hit.time_of_impact, vec(hit.normal)))
}

#[derive(Debug, Default)]
struct RayStats {
    closest_hits: usize,
    misses: usize,
    /// Closest hits compared on the normal (not near an edge, not from inside).
    normals_compared: usize,
    /// Results decided inside the band, or ties between two bodies.
    ambiguous: usize,
    worst_across: Real,
    worst_along: Real,
    worst_angle: Real,
    all_hits_total: usize,
}

/// Checks one ray: the closest hit and all hits against parry's per-body answers.
fn check_ray(scene: &Scene, o: Point3, d: Vec3, max: Real, stats: &mut RayStats) {
    let world = &scene.world;
    let f = QueryFilter::default();
    let closest = world.cast_ray(o, d, max, f).unwrap();
    let all = world.cast_ray_all(o, d, max, f).unwrap();
    let reach_band = BAND / d.norm();
    let mut ambiguous = false;
    // Per body: parry's nominal hit, and whether the hit is certain, ruled out, or in the band.
    let mut best: Option<(usize, Real, Vec3)> = None;
    let mut certain = Vec::new();
    for (i, (handle, pose, h)) in scene.bodies.iter().enumerate() {
        let nominal = parry_ray(pose, h, 0.0, &o, &d, max);
        let shrunk = parry_ray(pose, h, -BAND, &o, &d, (max - reach_band).max(0.0));
        let grown = parry_ray(pose, h, BAND, &o, &d, max + reach_band);
        let in_all = all.iter().find(|hit| hit.body == *handle);
        if shrunk.is_some() {
            assert!(
                in_all.is_some(),
                "all hits: missed body {i} at {o} along {d}"
            );
            certain.push(i);
        } else if grown.is_none() {
            assert!(
                in_all.is_none(),
                "all hits: false hit of body {i} at {o} along {d}"
            );
        } else if in_all.is_some() != nominal.is_some() {
            ambiguous = true;
        }
        if let Some((t, n)) = nominal
            && best.is_none_or(|(_, bt, _)| t < bt)
        {
            best = Some((i, t, n));
        }
    }
    stats.all_hits_total += all.len();
    // All hits: sorted by time, each body once, each one's time its closest hit.
    assert!(all.windows(2).all(|w| w[0].toi <= w[1].toi));
    if let Some(first) = all.first() {
        assert_eq!(
            Some(first.toi),
            closest.map(|c| c.toi),
            "all hits start at the closest"
        );
    }
    match (closest, best) {
        (None, None) => stats.misses += 1,
        (None, Some(_)) | (Some(_), None) => {
            // Only a hit in the band may be missed or found without parry agreeing.
            assert!(
                certain.is_empty(),
                "closest: a certain hit was missed at {o} along {d}"
            );
            ambiguous = true;
        }
        (Some(hit), Some((i, t, n))) => {
            stats.closest_hits += 1;
            let (handle, pose, h) = &scene.bodies[i];
            assert!((hit.point - (o + d * hit.toi)).norm() <= 1e-4 * (1.0 + hit.toi * d.norm()));
            if hit.body != *handle {
                // Another body: one hit at the same time up to rounding (overlapping boxes),
                // or one grazed inside the band before parry's first. Either way parry hits
                // it when grown by the band, at our time, and ours is not later than parry's.
                let ours = scene.bodies.iter().find(|b| b.0 == hit.body).unwrap();
                let (t2, _) = parry_ray(&ours.1, &ours.2, BAND, &o, &d, max + reach_band)
                    .expect("our body is hit by parry too, grown by the band");
                assert!(
                    (t2 - hit.toi) * d.norm() <= 2.0 * BAND,
                    "ours {} vs {t2}",
                    hit.toi
                );
                assert!(
                    (hit.toi - t) * d.norm() <= 2.0 * BAND,
                    "ours {} after parry's {t}",
                    hit.toi
                );
                ambiguous = true;
            } else {
                let dtoi = (hit.toi - t).abs();
                let cos = if n == Vec3::zeros() {
                    1.0
                } else {
                    d.dot(&n).abs() / d.norm()
                };
                let across = dtoi * d.norm() * cos;
                stats.worst_across = stats.worst_across.max(across);
                assert!(
                    across <= TOI_ACROSS_TOL,
                    "toi {} vs parry {t} at {o} along {d}",
                    hit.toi
                );
                if cos >= 0.1 {
                    let along = dtoi * d.norm();
                    stats.worst_along = stats.worst_along.max(along);
                    assert!(along <= TOI_ALONG_TOL, "toi {} vs parry {t}", hit.toi);
                }
                if hit.toi > 0.0 && faces_near(pose, h, &hit.point, EDGE_ZONE) <= 1 {
                    let a = angle(&hit.normal, &n);
                    stats.normals_compared += 1;
                    stats.worst_angle = stats.worst_angle.max(a);
                    assert!(a <= NORMAL_TOL, "normal {} vs parry {n}", hit.normal);
                } else if hit.toi == 0.0 {
                    assert_eq!(hit.normal, Vec3::zeros(), "a ray from inside has no normal");
                }
            }
        }
    }
    if ambiguous {
        stats.ambiguous += 1;
    }
}

/// 10,000 seeded random rays over 20 random scenes of 60 to 200 rotated boxes: the closest
/// hit is parry's (body, time within [`TOI_ACROSS_TOL`] / [`TOI_ALONG_TOL`], normal within
/// [`NORMAL_TOL`]), and all hits are the bodies parry hits.
///
/// Last run: 10,000 rays, 2,798 closest hits (2,363 compared on the normal), 4,842 bodies in
/// all hits, none ambiguous; worst time error 3.8e-6 m across the face, 7.0e-6 m along the ray,
/// worst normal 2.4e-7 rad.
#[test]
fn random_ray_casts_agree_with_parry() {
    let mut stats = RayStats::default();
    let mut rays = 0;
    for seed in 0..RAY_SCENES {
        let mut rng = ChaCha8Rng::seed_from_u64(1000 + seed);
        let n = rng.random_range(60..=200);
        let scene = random_scene(seed, n);
        for _ in 0..RAYS_PER_SCENE {
            let o = Point3::from(Vec3::from_fn(|_, _| rng.random_range(-7.0..7.0)));
            let dir = random_rotation(&mut rng) * Vec3::x();
            // Directions of several lengths: the time of impact is in its units.
            let d = dir * rng.random_range(0.2..3.0);
            let max = if rng.random_bool(0.1) {
                Real::INFINITY
            } else {
                rng.random_range(0.0..30.0) / d.norm()
            };
            check_ray(&scene, o, d, max, &mut stats);
            rays += 1;
        }
    }
    println!("{rays} rays: {stats:?}");
    assert_eq!(rays, 10_000);
    assert!(
        stats.closest_hits > 2_000,
        "the scenes are dense enough to test hits"
    );
    assert!(stats.normals_compared > 1_500);
    let share = stats.ambiguous as f64 / rays as f64;
    assert!(share <= MAX_AMBIGUOUS_SHARE, "{share}");
}

/// Box casts per scene and scenes: 10 x 200 = 2,000.
const CAST_SCENES: u64 = 10;
const CASTS_PER_SCENE: usize = 200;

/// How far our box cast's time of impact may be from parry's, as a distance along the
/// velocity, m. Parry finds it iteratively (a GJK ray cast on the boxes' Minkowski
/// difference), which stops off the exact time by up to 2.4e-3 m on these scenes (the
/// worst seen); ours is exact up to rounding, and every difference above [`CONFIRM_ABOVE`]
/// is checked to be parry's (see there). 5e-3 m is about twice the worst seen, and 10
/// times smaller than the smallest box, so a wrong face or a missed axis still fails.
const CAST_TOL: Real = 5e-3;

/// Where our time of impact and parry's differ by more than this along the velocity (m),
/// parry's exact overlap test (SAT for two cuboids) decides: the boxes must be apart
/// `CONFIRM_ABOVE` before our time and touching that much after it (the band on the
/// target). 1e-4 m is above our rounding (1e-6 m) and below parry's stopping error.
const CONFIRM_ABOVE: Real = 1e-4;

/// 2,000 seeded random box casts over 10 random scenes: the first body touched and its time
/// agree with parry's `cast_shapes` run on every body (time within [`CAST_TOL`]).
///
/// Last run: 653 hits, none ambiguous, worst difference 2.4e-3 m; the 13 differences above
/// [`CONFIRM_ABOVE`] were all parry's (ours confirmed by the overlap test).
#[test]
fn random_box_casts_agree_with_parry() {
    let (mut hits, mut ambiguous, mut worst): (usize, usize, Real) = (0, 0, 0.0);
    let mut confirmed = 0;
    let mut casts = 0;
    for seed in 0..CAST_SCENES {
        let mut rng = ChaCha8Rng::seed_from_u64(2000 + seed);
        let scene = random_scene(100 + seed, rng.random_range(40..=120));
        for _ in 0..CASTS_PER_SCENE {
            let h = random_half_extents(&mut rng) * 0.5;
            let c = Vec3::from_fn(|_, _| rng.random_range(-7.0..7.0));
            let pose = Pose::from_parts(c.into(), random_rotation(&mut rng));
            let v = random_rotation(&mut rng) * Vec3::x() * rng.random_range(0.5..4.0);
            let max = rng.random_range(0.0..20.0) / v.norm();
            let ours = scene
                .world
                .cast_box(h, pose, v, max, QueryFilter::default())
                .unwrap();
            casts += 1;
            let cast = |b: &(BodyHandle, Pose, Vec3), grow: Real, max: Real| {
                let opts = ShapeCastOptions::with_max_time_of_impact(max);
                cast_shapes(
                    &ppose(&pose),
                    pvec(&v),
                    &pcuboid(&h, 0.0),
                    &ppose(&b.1),
                    PVec::ZERO,
                    &pcuboid(&b.2, grow),
                    opts,
                )
                .expect("cuboids are supported")
                .map(|hit| hit.time_of_impact)
            };
            let band = BAND / v.norm();
            let nominal = scene
                .bodies
                .iter()
                .filter_map(|b| cast(b, 0.0, max).map(|t| (b.0, t)))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            let certain = scene
                .bodies
                .iter()
                .any(|b| cast(b, -BAND, (max - band).max(0.0)).is_some());
            match (ours, nominal) {
                (None, None) => {}
                (Some(hit), Some((body, t))) => {
                    hits += 1;
                    if hit.body == body {
                        let along = (hit.toi - t).abs() * v.norm();
                        worst = worst.max(along);
                        assert!(along <= CAST_TOL, "box cast toi {} vs parry {t}", hit.toi);
                        if along > CONFIRM_ABOVE && hit.toi > 0.0 {
                            // Which is right? Parry's own overlap test, just before and just
                            // after our time: apart (shrunk), then touching (grown).
                            let b = scene.bodies.iter().find(|b| b.0 == body).unwrap();
                            let at = |dt: Real, grow: Real| {
                                let mut p = pose;
                                p.translation.vector += v * (hit.toi + dt);
                                parry3d::query::intersection_test(
                                    &ppose(&p),
                                    &pcuboid(&h, 0.0),
                                    &ppose(&b.1),
                                    &pcuboid(&b.2, grow),
                                )
                                .expect("cuboids are supported")
                                .intersecting
                            };
                            let step = CONFIRM_ABOVE / v.norm();
                            assert!(!at(-step, -BAND), "touching before our toi {}", hit.toi);
                            assert!(at(step, BAND), "apart after our toi {}", hit.toi);
                            confirmed += 1;
                        }
                    } else {
                        // Another body touched as early (a tie), or grazed inside the band
                        // first: parry touches it when grown, at our time, and ours is not
                        // later than parry's first.
                        let b = scene.bodies.iter().find(|b| b.0 == hit.body).unwrap();
                        let t2 = cast(b, BAND, max + band).expect("parry touches it grown");
                        assert!((t2 - hit.toi) * v.norm() <= CAST_TOL, "{} vs {t2}", hit.toi);
                        assert!(
                            (hit.toi - t) * v.norm() <= CAST_TOL,
                            "{} after {t}",
                            hit.toi
                        );
                        ambiguous += 1;
                    }
                    if hit.toi > 0.0 {
                        assert!((hit.normal.norm() - 1.0).abs() < 1e-4 && hit.normal.dot(&v) < 0.0);
                    }
                }
                (Some(hit), None) => {
                    // Parry misses: ours must be a touch in the band.
                    let b = scene.bodies.iter().find(|b| b.0 == hit.body).unwrap();
                    assert!(cast(b, BAND, max + band).is_some(), "a false box hit");
                    ambiguous += 1;
                }
                (None, Some(_)) => {
                    assert!(!certain, "a certain box hit was missed");
                    ambiguous += 1;
                }
            }
        }
    }
    println!(
        "{casts} box casts: {hits} hits, {ambiguous} ambiguous, worst {worst} m, \
         {confirmed} times off parry's by more than {CONFIRM_ABOVE} m confirmed ours"
    );
    assert_eq!(casts, 2_000);
    assert!(hits > 500);
    assert!(ambiguous as f64 / casts as f64 <= MAX_AMBIGUOUS_SHARE);
}
