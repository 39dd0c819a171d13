//! The random pairs: three families of placements around touching, drawn from one seeded
//! stream.

use super::*;

pub(super) fn overlapping(case: &Case) -> bool {
    let (a, b) = case.boxes();
    crate::tests::reference::Sat64::new(&a, &b, 1e-12).max() <= 0.0
}

pub(super) fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    rng.random_range(lo.ln()..hi.ln()).exp()
}

/// A uniformly random rotation (a normalised point of the 4-ball).
pub(super) fn random_rotation(rng: &mut ChaCha8Rng) -> Rot {
    loop {
        let q: [Real; 4] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
        let n2: Real = q.iter().map(|c| c * c).sum();
        if n2 > 1e-3 && n2 <= 1.0 {
            return Rot::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3]));
        }
    }
}

/// Half extents from 0.01 to 5, aspect ratios up to 20.
pub(super) fn random_cuboid(rng: &mut ChaCha8Rng) -> Cuboid {
    let longest = log_uniform(rng, 0.01, 5.0);
    let h: [f64; 3] = std::array::from_fn(|_| (longest / log_uniform(rng, 1.0, 20.0)).max(0.005));
    let mut h = h;
    h[rng.random_range(0..3)] = longest;
    Cuboid::new(Vec3::new(h[0] as Real, h[1] as Real, h[2] as Real))
}

/// B at `base + dir * c`, with the largest `c` at which the boxes still overlap found by
/// bisection on the exact SAT separation (the set of overlapping `c` is an interval, the
/// Minkowski difference being convex, and `base` lies in it), then moved to one of four
/// classes: anywhere inside, shallow, apart within the margin, apart beyond it.
pub(super) fn place(
    rng: &mut ChaCha8Rng,
    a: Cuboid,
    pose_a: Pose,
    b: Cuboid,
    rot_b: Rot,
    base: Vec3,
    dir: Vec3,
) -> Case {
    let at = |c: f64| Case {
        a,
        pose_a,
        b,
        pose_b: Pose::from_parts(Translation3::from(base + dir * c as Real), rot_b),
    };
    let overlapping = |c: f64| overlapping(&at(c));
    let far = (a.half_extents.norm() + b.half_extents.norm()) as f64 * 2.0 + 1.0;
    let (mut lo, mut hi) = (0.0, far);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if overlapping(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let touch = lo;
    let small = a.half_extents.max().min(b.half_extents.max()) as f64;
    let c = match rng.random_range(0..8) {
        0 | 1 => touch * rng.random_range(0.0..1.0),
        2..=4 => touch - small * log_uniform(rng, 1e-4, 0.1),
        5 | 6 => touch + rng.random_range(0.0..1.0) * MARGIN as f64,
        _ => touch + rng.random_range(1.0..3.0) * MARGIN as f64,
    };
    at(c)
}

/// Two random boxes and a random pose of A near the origin (B's placement is the family's),
/// drawn in the order every family shares: A's size, B's size, A's position and rotation.
fn random_boxes(rng: &mut ChaCha8Rng) -> (Cuboid, Pose, Cuboid) {
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
    (a, pose_a, b)
}

/// Any two boxes, any rotations, B approaching A from a random direction.
pub(super) fn random_case(rng: &mut ChaCha8Rng) -> Case {
    let (a, pose_a, b) = random_boxes(rng);
    let rot_b = random_rotation(rng);
    let dir = random_rotation(rng) * Vec3::x();
    place(rng, a, pose_a, b, rot_b, pose_a.translation.vector, dir)
}

/// B approaching one of A's corners or edges, where the closest pair can be a vertex against
/// an edge or a vertex (no SAT axis: the vertex contacts) or two crossing edges.
pub(super) fn corner_case(rng: &mut ChaCha8Rng) -> Case {
    let (a, pose_a, b) = random_boxes(rng);
    let rot_b = random_rotation(rng);
    // A corner (all three signs) or an edge (one coordinate anywhere along it) of A.
    let mut target = a.vertex(rng.random_range(0..8)).coords;
    if rng.random_bool(0.5) {
        let k = rng.random_range(0..3);
        target[k] *= rng.random_range(-1.0..1.0);
    }
    let wobble = random_rotation(rng) * Vec3::x() * 0.2 * target.norm();
    let dir = pose_a.rotation * (target + wobble).normalize();
    place(rng, a, pose_a, b, rot_b, pose_a.translation.vector, dir)
}

/// B resting on one of A's faces: its rotation one of the 24 axis-aligned ones relative to A,
/// tilted by up to 6 degrees (either side of the 3 degree face-like edge angle), its centre
/// anywhere over the face and up to 20 % beyond its edges (overhanging), approaching along the
/// face normal. These are the pairs where faces tie, edges near face normals compete with them,
/// and the preferences decide.
pub(super) fn stacked_case(rng: &mut ChaCha8Rng) -> Case {
    let (a, pose_a, b) = random_boxes(rng);
    let quarter =
        |rng: &mut ChaCha8Rng| rng.random_range(0..4) as Real * std::f32::consts::FRAC_PI_2;
    let aligned = Rot::from_euler_angles(quarter(rng), quarter(rng), quarter(rng));
    let tilt_axis = Unit::new_normalize(random_rotation(rng) * Vec3::x());
    let tilt = Rot::from_axis_angle(&tilt_axis, rng.random_range(0.0..6.0_f32).to_radians());
    let rot_b = pose_a.rotation * tilt * aligned;
    let axis = rng.random_range(0..3);
    let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    loop {
        let mut lateral = Vec3::zeros();
        for k in (0..3).filter(|&k| k != axis) {
            lateral[k] = rng.random_range(-1.2..1.2) * a.half_extents[k];
        }
        let base = pose_a * tumble_geometry::Point3::from(lateral);
        let dir = pose_a.rotation * Vec3::ith(axis, sign);
        let case = place(rng, a, pose_a, b, rot_b, base.coords, dir);
        // The base must overlap for the bisection to start inside; a base beyond the edge of a
        // box too small to reach back is drawn again.
        let start = Case {
            pose_b: Pose::from_parts(Translation3::from(base.coords), rot_b),
            ..case
        };
        if overlapping(&start) {
            return case;
        }
    }
}
