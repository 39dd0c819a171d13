//! Box-box narrow phase on 10,000 seeded pairs: Tumble's `collide_cuboids` (full manifold) beside
//! parry3d's `contact` (GJK + EPA, one deepest point) and parry3d's cuboid-cuboid contact manifold
//! (SAT + clipping, the fair manifold-to-manifold comparison), in one criterion group.
//!
//! The pairs: half extents from 0.01 to 10 with aspect ratios up to 100:1, random orientations,
//! centres along a random direction at 0.15 to 0.6 times the sum of the circumradii, which makes
//! roughly half of them touch. Conversions to parry's types happen before timing.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use parry3d::math::{Pose as PPose, Rotation as PRot, Vector as PVec};
use parry3d::query::{ContactManifold, details::contact_manifold_cuboid_cuboid};
use parry3d::shape::Cuboid as PCuboid;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{
    Cuboid, Pose, Real, Rot, Vec3, nalgebra::Quaternion, nalgebra::Translation3,
};
use tumble_narrow::collide_cuboids;

/// Pairs per iteration.
const PAIRS: usize = 10_000;
/// Speculative margin: 2 cm, as in the tests.
const MARGIN: Real = 0.02;

struct Pair {
    a: Cuboid,
    pose_a: Pose,
    b: Cuboid,
    pose_b: Pose,
}

fn random_rotation(rng: &mut ChaCha8Rng) -> Rot {
    loop {
        let q: [Real; 4] = std::array::from_fn(|_| rng.random_range(-1.0..1.0));
        let n2: Real = q.iter().map(|c| c * c).sum();
        if n2 > 1e-4 && n2 <= 1.0 {
            return Rot::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3]));
        }
    }
}

fn random_cuboid(rng: &mut ChaCha8Rng) -> Cuboid {
    let log = |rng: &mut ChaCha8Rng, lo: Real, hi: Real| rng.random_range(lo.ln()..hi.ln()).exp();
    let longest = log(rng, 0.01, 10.0);
    let mut h = [
        longest,
        (longest / log(rng, 1.0, 100.0)).max(0.01),
        (longest / log(rng, 1.0, 100.0)).max(0.01),
    ];
    let first = rng.random_range(0..3);
    h.swap(0, first);
    Cuboid::new(Vec3::new(h[0], h[1], h[2]))
}

fn random_pairs(n: usize, seed: u64) -> Vec<Pair> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let (a, b) = (random_cuboid(&mut rng), random_cuboid(&mut rng));
            let pose_a = Pose::from_parts(
                Translation3::new(
                    rng.random_range(-2.0..2.0),
                    rng.random_range(-2.0..2.0),
                    rng.random_range(-2.0..2.0),
                ),
                random_rotation(&mut rng),
            );
            let dir = random_rotation(&mut rng) * Vec3::x();
            let reach =
                (a.half_extents.norm() + b.half_extents.norm()) * rng.random_range(0.15..0.6);
            let pose_b = Pose::from_parts(
                Translation3::from(pose_a.translation.vector + dir * reach),
                random_rotation(&mut rng),
            );
            Pair {
                a,
                pose_a,
                b,
                pose_b,
            }
        })
        .collect()
}

fn to_parry(pose: &Pose) -> PPose {
    let t = pose.translation.vector;
    let q = pose.rotation.quaternion().coords; // (i, j, k, w)
    PPose::from_parts(
        PVec::new(t.x, t.y, t.z),
        PRot::from_xyzw(q.x, q.y, q.z, q.w),
    )
}

fn to_parry_box(c: &Cuboid) -> PCuboid {
    PCuboid::new(PVec::new(
        c.half_extents.x,
        c.half_extents.y,
        c.half_extents.z,
    ))
}

fn narrow_phase(c: &mut Criterion) {
    let pairs = random_pairs(PAIRS, 2024);
    let parry_pairs: Vec<(PPose, PCuboid, PPose, PCuboid)> = pairs
        .iter()
        .map(|p| {
            (
                to_parry(&p.pose_a),
                to_parry_box(&p.a),
                to_parry(&p.pose_b),
                to_parry_box(&p.b),
            )
        })
        .collect();
    let touching = pairs
        .iter()
        .filter(|p| collide_cuboids(&p.a, &p.pose_a, &p.b, &p.pose_b, MARGIN).is_some())
        .count();
    println!("narrow_phase: {touching} of {PAIRS} pairs touch within the {MARGIN} m margin");

    let mut group = c.benchmark_group("narrow_phase");
    group.throughput(Throughput::Elements(PAIRS as u64));
    group.bench_function("tumble_collide_cuboids", |bench| {
        bench.iter(|| {
            let mut points = 0usize;
            for p in black_box(&pairs) {
                if let Some(m) = collide_cuboids(&p.a, &p.pose_a, &p.b, &p.pose_b, MARGIN) {
                    points += m.len as usize;
                }
            }
            points
        })
    });
    group.bench_function("parry_contact", |bench| {
        bench.iter(|| {
            let mut hits = 0usize;
            for (pa, sa, pb, sb) in black_box(&parry_pairs) {
                if let Ok(Some(_)) = parry3d::query::contact(pa, sa, pb, sb, MARGIN) {
                    hits += 1;
                }
            }
            hits
        })
    });
    group.bench_function("parry_cuboid_manifold", |bench| {
        let mut manifold = ContactManifold::<(), ()>::new();
        bench.iter(|| {
            let mut points = 0usize;
            for (pa, sa, pb, sb) in black_box(&parry_pairs) {
                // A fresh manifold each time: no reuse of last frame's contacts, like ours.
                manifold.clear();
                let pos12 = pa.inv_mul(pb);
                contact_manifold_cuboid_cuboid(&pos12, sa, sb, MARGIN, &mut manifold);
                points += manifold.points.len();
            }
            points
        })
    });
    group.finish();
}

criterion_group!(benches, narrow_phase);
criterion_main!(benches);
