//! Scenes for the GPU collision tests (`gpu_collision.rs`, `gpu_narrow.rs`,
//! `gpu_broad_phase.rs`) as the GPU stages take them, and conversions for their CPU twins.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Aabb, Pose, Rot, Vec3, nalgebra::Translation3};
use tumble_gpu::collision::CollisionConfig;
use tumble_gpu::layout::{GpuAabb, GpuPose, GpuShape, GpuVelocity};
use tumble_gpu::{CollisionSnapshot, GpuCollision, GpuContext, ReadbackRequest};

use crate::scene_support::random_vec;

/// One collision step that reads back the pairs and the AABBs: the readback, and its AABBs as
/// the CPU broad phase takes them.
pub fn step_pairs_and_aabbs(gpu: &mut GpuCollision) -> (CollisionSnapshot, Vec<Aabb>) {
    let snap = gpu
        .step_and_read(ReadbackRequest {
            pairs: true,
            aabbs: true,
            ..Default::default()
        })
        .unwrap();
    let aabbs = snap.aabbs.iter().map(to_aabb).collect();
    (snap, aabbs)
}

/// A scene as the GPU takes it.
pub struct Scene {
    /// Poses.
    pub poses: Vec<GpuPose>,
    /// Velocities.
    pub velocities: Vec<GpuVelocity>,
    /// Shapes (static flag included).
    pub shapes: Vec<GpuShape>,
}

/// A seeded random rotation.
pub fn random_rotation(rng: &mut ChaCha8Rng) -> Rot {
    Rot::from_euler_angles(
        rng.random_range(-3.2..3.2),
        rng.random_range(-1.6..1.6),
        rng.random_range(-3.2..3.2),
    )
}

/// `n` boxes scattered in a cube sized so that each overlaps a few others, 10 % static.
pub fn random_scene(n: usize, seed: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // About 1.3 m of space per box along each axis: boxes of 0.2 to 1.2 m then overlap about
    // three neighbours each, a dense but realistic pile.
    let side = 1.3 * (n as f32).cbrt();
    let mut scene = Scene {
        poses: Vec::new(),
        velocities: Vec::new(),
        shapes: Vec::new(),
    };
    for _ in 0..n {
        let is_static = rng.random_bool(0.1);
        let h = random_vec(&mut rng, 0.1..0.6);
        let t = random_vec(&mut rng, 0.0..side);
        let pose = Pose::from_parts(Translation3::from(t), random_rotation(&mut rng));
        let mut v = || random_vec(&mut rng, -2.0..2.0);
        let (lin, ang) = if is_static {
            (Vec3::zeros(), Vec3::zeros())
        } else {
            (v(), v())
        };
        scene.poses.push(GpuPose::from_pose(&pose));
        scene.velocities.push(GpuVelocity::new(lin, ang));
        scene.shapes.push(GpuShape::cuboid(
            &tumble_geometry::Cuboid::new(h),
            is_static,
        ));
    }
    scene
}

/// The GPU collision stages with `scene` uploaded.
pub fn collision(ctx: &GpuContext, scene: &Scene, config: CollisionConfig) -> GpuCollision {
    let mut c = GpuCollision::new(ctx, config).expect("pipelines build");
    c.set_bodies(&scene.poses, &scene.velocities, &scene.shapes)
        .expect("valid scene");
    c
}

/// A GPU AABB as `tumble_geometry`'s.
pub fn to_aabb(b: &GpuAabb) -> Aabb {
    tumble_gpu::kernels::aabb_from_gpu(b)
}

/// Each body's static flag.
pub fn static_flags(scene: &Scene) -> Vec<bool> {
    scene.shapes.iter().map(GpuShape::is_static).collect()
}

/// Pairs of boxes near contact, one pair per cell of a grid 6 m apart: faces resting on
/// faces with small tilts, crossed edges, and pairs in general position, some overlapping,
/// some apart within the margin, some beyond it.
pub fn contact_pairs(pairs: usize, seed: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut scene = Scene {
        poses: vec![],
        velocities: vec![],
        shapes: vec![],
    };
    let per_axis = (pairs as f32).cbrt().ceil() as usize;
    let spacing = 6.0;
    let origin = -0.5 * spacing * per_axis as f32;
    for k in 0..pairs {
        let cell = Vec3::new(
            (k % per_axis) as f32,
            ((k / per_axis) % per_axis) as f32,
            (k / (per_axis * per_axis)) as f32,
        );
        let ha = random_vec(&mut rng, 0.2..1.2);
        let hb = random_vec(&mut rng, 0.2..1.2);
        let rot_a = random_rotation(&mut rng);
        let ta = cell * spacing + Vec3::repeat(origin);
        let pose_b = match rng.random_range(0..10) {
            // B on one of A's faces: aligned up to a small tilt (which makes face choices and
            // hysteresis matter), slid sideways, from 2 cm deep to 2 cm apart.
            0..=3 => {
                let axis = rng.random_range(0..3);
                let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
                let tilt = Rot::from_euler_angles(
                    rng.random_range(-0.05..0.05),
                    rng.random_range(-0.05..0.05),
                    rng.random_range(-0.05..0.05),
                );
                let rot_b = rot_a * tilt;
                let n = rot_a * Vec3::ith(axis, sign);
                let radius_b = (0..3)
                    .map(|j| (rot_b * Vec3::ith(j, 1.0)).dot(&n).abs() * hb[j])
                    .sum::<f32>();
                let mut lateral = Vec3::zeros();
                for j in (0..3).filter(|&j| j != axis) {
                    lateral += rot_a * Vec3::ith(j, rng.random_range(-ha[j]..ha[j]));
                }
                let gap = rng.random_range(-0.02..0.02);
                Pose::from_parts(
                    Translation3::from(ta + n * (ha[axis] + radius_b + gap) + lateral),
                    rot_b,
                )
            }
            // Anywhere around A, from deep overlap to just past touching.
            _ => {
                let dir = random_vec(&mut rng, -1.0..1.0)
                    .try_normalize(1e-3)
                    .unwrap_or(Vec3::x());
                let reach = rng.random_range(0.3..1.05) * (ha.norm() + hb.norm());
                Pose::from_parts(
                    Translation3::from(ta + dir * reach),
                    random_rotation(&mut rng),
                )
            }
        };
        let pose_a = Pose::from_parts(Translation3::from(ta), rot_a);
        for (pose, h) in [(pose_a, ha), (pose_b, hb)] {
            scene.poses.push(GpuPose::from_pose(&pose));
            scene.velocities.push(GpuVelocity::default());
            scene
                .shapes
                .push(GpuShape::cuboid(&tumble_geometry::Cuboid::new(h), false));
        }
    }
    scene
}
