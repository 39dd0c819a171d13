//! AABB overlap and point queries against parry3d.

use parry3d::query::{PointQuery, intersection_test};
use tumble::QueryFilter;

use super::*;

/// Scenes, and AABBs and points per scene: 20 x 500 AABBs and 20 x 500 points (10,000 each),
/// each point also projected.
const SCENES: u64 = 20;
const PER_SCENE: usize = 500;

/// How far our nearest distance may be from parry's, m: both clamp the point in the box's
/// frame in `f32`; the frames differ by a few ulps of the coordinates of up to 10 m (1e-6 m).
const DISTANCE_TOL: Real = 2e-5;

/// Largest share of queries with a body inside the presence band: a box face within 1e-4 m
/// of a random AABB face or point is rare (last run: 7 of 10,000 AABBs, 6 of 10,000 points).
const MAX_AMBIGUOUS_SHARE: f64 = 0.01;

/// Per body, parry's verdict on the band: `Some(true)` certainly in, `Some(false)` certainly
/// out, `None` within the band.
fn banded(inside: impl Fn(Real) -> bool) -> Option<bool> {
    match (inside(-BAND), inside(BAND)) {
        (true, _) => Some(true),
        (false, false) => Some(false),
        (false, true) => None,
    }
}

/// 10,000 random AABBs over 20 random scenes: `bodies_in_aabb` returns every body that
/// parry's `intersection_test` finds overlapping the AABB's box when shrunk by the band, and
/// none that it finds apart when grown by it.
#[test]
fn random_aabb_queries_agree_with_parry() {
    let (mut queries, mut found, mut ambiguous) = (0, 0, 0);
    for seed in 0..SCENES {
        let mut rng = ChaCha8Rng::seed_from_u64(3000 + seed);
        let scene = random_scene(200 + seed, rng.random_range(60..=200));
        for _ in 0..PER_SCENE {
            let c = Vec3::from_fn(|_, _| rng.random_range(-7.0..7.0));
            let e = random_half_extents(&mut rng) * 1.5;
            let aabb = Aabb::new((c - e).into(), (c + e).into());
            let ours = scene
                .world
                .bodies_in_aabb(aabb, QueryFilter::default())
                .unwrap();
            queries += 1;
            found += ours.len();
            let query_pose = ppose(&Pose::translation(c.x, c.y, c.z));
            let mut unsure = false;
            for (handle, pose, h) in &scene.bodies {
                let meets = |grow: Real| {
                    intersection_test(
                        &query_pose,
                        &pcuboid(&e, 0.0),
                        &ppose(pose),
                        &pcuboid(h, grow),
                    )
                    .expect("cuboids are supported")
                    .intersecting
                };
                match banded(meets) {
                    Some(true) => assert!(ours.contains(handle), "missed {handle:?} in {aabb:?}"),
                    Some(false) => assert!(!ours.contains(handle), "false {handle:?} in {aabb:?}"),
                    None => unsure = true,
                }
            }
            // In the world's order, each once.
            let order: Vec<usize> = ours
                .iter()
                .map(|h| scene.world.handles().iter().position(|x| x == h).unwrap())
                .collect();
            assert!(order.windows(2).all(|w| w[0] < w[1]));
            ambiguous += usize::from(unsure);
        }
    }
    println!("{queries} AABB queries: {found} bodies found, {ambiguous} ambiguous");
    assert_eq!(queries, 10_000);
    assert!(found > 10_000, "the queries find bodies");
    assert!(ambiguous as f64 / queries as f64 <= MAX_AMBIGUOUS_SHARE);
}

/// 10,000 random points over 20 random scenes: `bodies_containing_point` agrees with
/// parry's `contains_point` on the banded boxes, and `project_point` finds the body parry's
/// `distance_to_point` puts nearest, at the same distance.
#[test]
fn random_point_queries_agree_with_parry() {
    let (mut queries, mut inside, mut ambiguous, mut worst) = (0, 0, 0, 0.0 as Real);
    for seed in 0..SCENES {
        let mut rng = ChaCha8Rng::seed_from_u64(4000 + seed);
        let scene = random_scene(300 + seed, rng.random_range(60..=200));
        for _ in 0..PER_SCENE {
            // Half the points near a random body (often inside it), half anywhere.
            let p = if rng.random_bool(0.5) {
                let (_, pose, h) = &scene.bodies[rng.random_range(0..scene.bodies.len())];
                let local = Point3::from(Vec3::from_fn(|k, _| h[k] * rng.random_range(-1.5..1.5)));
                pose * local
            } else {
                Point3::from(Vec3::from_fn(|_, _| rng.random_range(-7.0..7.0)))
            };
            let pp = PVec::new(p.x, p.y, p.z);
            let f = QueryFilter::default();
            let ours = scene.world.bodies_containing_point(p, f).unwrap();
            queries += 1;
            inside += ours.len();
            let mut unsure = false;
            let mut nearest: Option<(BodyHandle, Real)> = None;
            for (handle, pose, h) in &scene.bodies {
                let contains = |grow: Real| pcuboid(h, grow).contains_point(&ppose(pose), pp);
                match banded(contains) {
                    Some(true) => assert!(ours.contains(handle), "missed {handle:?} at {p}"),
                    Some(false) => assert!(!ours.contains(handle), "false {handle:?} at {p}"),
                    None => unsure = true,
                }
                let dist = pcuboid(h, 0.0).distance_to_point(&ppose(pose), pp, true);
                if nearest.is_none_or(|(_, d)| dist < d) {
                    nearest = Some((*handle, dist));
                }
            }
            ambiguous += usize::from(unsure);
            let max_dist = rng.random_range(0.0..3.0);
            let proj = scene.world.project_point(p, max_dist, f).unwrap();
            match (proj, nearest) {
                (Some(hit), Some((body, d))) if d <= max_dist + DISTANCE_TOL => {
                    let err = (hit.distance - d).abs();
                    worst = worst.max(err);
                    assert!(
                        err <= DISTANCE_TOL,
                        "distance {} vs parry {d}",
                        hit.distance
                    );
                    assert!(((hit.point - p).norm() - hit.distance).abs() <= DISTANCE_TOL);
                    // A different body only at the same distance (two boxes equally near).
                    if hit.body != body {
                        let b = scene.bodies.iter().find(|b| b.0 == hit.body).unwrap();
                        let d2 = pcuboid(&b.2, 0.0).distance_to_point(&ppose(&b.1), pp, true);
                        assert!((d2 - d).abs() <= DISTANCE_TOL);
                    }
                    if d == 0.0 {
                        assert!(ours.contains(&hit.body) || unsure);
                    }
                }
                (None, Some((_, d))) => assert!(d >= max_dist - DISTANCE_TOL, "{d} {max_dist}"),
                (None, None) => {}
                (hit, nearest) => panic!("project_point {hit:?} vs parry {nearest:?}"),
            }
        }
    }
    println!(
        "{queries} point queries: {inside} containing bodies, {ambiguous} ambiguous, \
         worst distance error {worst} m"
    );
    assert_eq!(queries, 10_000);
    assert!(inside > 2_000, "the points land in bodies");
    assert!(ambiguous as f64 / queries as f64 <= MAX_AMBIGUOUS_SHARE);
}
