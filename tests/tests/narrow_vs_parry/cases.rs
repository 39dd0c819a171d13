//! The random pairs, and the area of a clipped polygon's hull.

use super::*;

/// A uniformly random rotation (normalised point of the unit 4-ball).
pub(super) fn random_rotation(rng: &mut ChaCha8Rng) -> Rot {
    loop {
        let q: [Real; 4] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
        let n2: Real = q.iter().map(|c| c * c).sum();
        if n2 > 1e-4 && n2 <= 1.0 {
            let quat = tumble_geometry::nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]);
            return Rot::from_quaternion(quat);
        }
    }
}

pub(super) fn log_uniform(rng: &mut ChaCha8Rng, lo: Real, hi: Real) -> Real {
    (rng.random_range(lo.ln()..hi.ln())).exp()
}

/// Half extents from 0.01 to 10 with aspect ratios up to 100:1, long axis anywhere.
pub(super) fn random_cuboid(rng: &mut ChaCha8Rng) -> Cuboid {
    let longest = log_uniform(rng, 0.01, 10.0);
    let mut h = [longest, 0.0, 0.0];
    for side in &mut h[1..] {
        *side = (longest / log_uniform(rng, 1.0, 100.0)).max(0.01);
    }
    let first = rng.random_range(0..3);
    h.swap(0, first);
    Cuboid::new(Vec3::new(h[0], h[1], h[2]))
}

/// A random pair: half overlapping, a quarter apart within the margin, a quarter beyond it.
pub(super) fn random_pair(rng: &mut ChaCha8Rng) -> (Cuboid, Pose, Cuboid, Pose) {
    let a = random_cuboid(rng);
    let b = random_cuboid(rng);
    let pose_a = Pose::from_parts(
        Translation3::new(
            rng.random_range(-2.0..2.0),
            rng.random_range(-2.0..2.0),
            rng.random_range(-2.0..2.0),
        ),
        random_rotation(rng),
    );
    let rot_b = random_rotation(rng);
    let dir = random_rotation(rng) * Vec3::x();
    let place = |c: Real| {
        Pose::from_parts(
            Translation3::from(pose_a.translation.vector + dir * c),
            rot_b,
        )
    };
    // The signed distance grows monotonically with the centre distance along a ray (the boxes are
    // centrally symmetric, so it is convex with its minimum at c = 0): bisect on the exact one.
    let far = a.half_extents.norm() + b.half_extents.norm() + 4.0 * MARGIN;
    let bisect = |target: Real| {
        let (mut lo, mut hi) = (0.0, far);
        for _ in 0..50 {
            let mid = 0.5 * (lo + hi);
            let d = exact_signed_distance(&Box64::new(&a, &pose_a), &Box64::new(&b, &place(mid)));
            if d > target as f64 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        0.5 * (lo + hi)
    };
    let touch = bisect(0.0);
    let class = rng.random_range(0..4);
    let c = match class {
        // Overlapping: half anywhere down to the centres coinciding, half shallow.
        0 => touch * rng.random_range(0.0..1.0),
        1 => touch * (1.0 - log_uniform(rng, 1e-4, 0.05)),
        2 => bisect(rng.random_range(0.0..MARGIN)),
        _ => bisect(rng.random_range(MARGIN..3.0 * MARGIN)),
    };
    (a, pose_a, b, place(c))
}

/// Area of the convex hull of `points`, seen along `normal` (gift wrapping; at most 8 points).
pub(super) fn hull_area(points: &[Point3], normal: &Vec3) -> Real {
    let u = normal
        .cross(&if normal.x.abs() < 0.6 {
            Vec3::x()
        } else {
            Vec3::y()
        })
        .normalize();
    let v = normal.cross(&u);
    let p2: Vec<(Real, Real)> = points
        .iter()
        .map(|p| (p.coords.dot(&u), p.coords.dot(&v)))
        .collect();
    if p2.len() < 3 {
        return 0.0;
    }
    let start = (0..p2.len())
        .min_by(|&i, &j| p2[i].0.total_cmp(&p2[j].0))
        .unwrap();
    let mut hull = vec![start];
    let mut current = start;
    loop {
        let mut next = (current + 1) % p2.len();
        for k in 0..p2.len() {
            let (o, a, b) = (p2[current], p2[next], p2[k]);
            let cross = (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0);
            if cross < 0.0 {
                next = k;
            }
        }
        if next == start || hull.len() > p2.len() {
            break;
        }
        hull.push(next);
        current = next;
    }
    let n = hull.len();
    (0..n)
        .map(|k| {
            let (p, q) = (p2[hull[k]], p2[hull[(k + 1) % n]]);
            p.0 * q.1 - q.0 * p.1
        })
        .sum::<Real>()
        .abs()
        * 0.5
}
