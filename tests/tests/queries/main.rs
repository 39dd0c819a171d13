//! The world's spatial queries cross-checked against parry3d on seeded random scenes of
//! rotated boxes of varied sizes, plus the queries' own contracts (stepped poses, filters,
//! bad input).
//!
//! The reference is parry's per-shape queries (`RayCast`, `PointQuery`,
//! `intersection_test`, `cast_shapes`) over every body of the world: a brute force that shares
//! nothing with the world's tree or with tumble-geometry's slab and swept SAT code.
//!
//! Presence (is a body hit, overlapped, does it contain the point) is decided with a band:
//! parry's answer for the body shrunk by [`BAND`] on every side must be found by us, and
//! parry's answer for the body grown by `BAND` must bound ours (nothing we report may miss the
//! grown body). Bodies inside the band can go either way in `f32` and are counted, not
//! judged; the counts are bounded so that a systematic error cannot hide there.

mod casts;
mod contracts;
mod overlaps;

use parry3d::math::{Pose as PPose, Rotation as PRot, Vector as PVec};
use parry3d::shape::Cuboid as PCuboid;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble::prelude::*;
use tumble::{Aabb, Cuboid};

/// The presence band, m: 1e-4 m. The scenes' coordinates reach 10 m, where an `f32` ulp is
/// 1e-6 m; the change of frame into a box adds a few ulps per product, both in parry and
/// here, so the two disagree by about 1e-5 m at worst. The band is ten times that, and far
/// below the smallest box (5 cm), so shrinking a box by it leaves a box.
const BAND: Real = 1e-4;

/// One random scene: a world on the CPU backend and, per body, its handle, pose and size.
struct Scene {
    world: World,
    bodies: Vec<(BodyHandle, Pose, Vec3)>,
}

/// A random unit rotation (uniform: a normalized 4D Gaussian-ish sample).
fn random_rotation(rng: &mut ChaCha8Rng) -> Rot {
    loop {
        let q = nalgebra::Quaternion::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let n = q.norm();
        if n > 0.1 && n <= 1.0 {
            return Rot::new_normalize(q);
        }
    }
}

/// A random half extent per axis, log-uniform in 5 cm to 2 m, so thin plates, rods and
/// cubes all occur.
fn random_half_extents(rng: &mut ChaCha8Rng) -> Vec3 {
    Vec3::from_fn(|_, _| (rng.random_range(0.05f32.ln()..2.0f32.ln())).exp())
}

/// `n` rotated boxes of varied sizes with centres in a 10 m cube about the origin (they may
/// overlap: the world is never stepped), half fixed and half dynamic.
fn random_scene(seed: u64, n: usize) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let config = WorldConfig {
        backend: Backend::Cpu,
        ..Default::default()
    };
    let mut world = World::new(config).unwrap();
    let bodies = (0..n)
        .map(|_| {
            let h = random_half_extents(&mut rng);
            let c = Vec3::from_fn(|_, _| rng.random_range(-5.0..5.0));
            let pose = Pose::from_parts(c.into(), random_rotation(&mut rng));
            let desc = if rng.random_bool(0.5) {
                BodyDesc::fixed()
            } else {
                BodyDesc::dynamic()
            };
            let handle = world.add_body(desc.cuboid(h).pose(pose)).unwrap();
            // The world renormalizes nothing here (a unit rotation), but read it back anyway:
            // the reference must see exactly the poses the queries see.
            (handle, world.pose(handle).unwrap(), h)
        })
        .collect();
    Scene { world, bodies }
}

/// Parry's pose of ours.
fn ppose(p: &Pose) -> PPose {
    let t = p.translation.vector;
    let q = p.rotation.coords; // (i, j, k, w)
    PPose::from_parts(
        PVec::new(t.x, t.y, t.z),
        PRot::from_xyzw(q.x, q.y, q.z, q.w),
    )
}

/// Parry's box of half extents `h` grown by `grow` on every side (negative: shrunk).
fn pcuboid(h: &Vec3, grow: Real) -> PCuboid {
    PCuboid::new(PVec::new(h.x + grow, h.y + grow, h.z + grow))
}

fn pvec(v: &Vec3) -> PVec {
    PVec::new(v.x, v.y, v.z)
}

fn vec(v: PVec) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// The angle between two unit vectors, rad.
fn angle(a: &Vec3, b: &Vec3) -> Real {
    a.cross(b).norm().atan2(a.dot(b))
}

/// How many of the three local coordinates of world point `p` lie within `d` of the face of
/// the box (`h` at `pose`) on their axis: 1 on a face, 2 near an edge, 3 near a corner.
fn faces_near(pose: &Pose, h: &Vec3, p: &Point3, d: Real) -> usize {
    let local = pose.inverse_transform_point(p);
    (0..3)
        .filter(|&k| (local[k].abs() - h[k]).abs() <= d)
        .count()
}
