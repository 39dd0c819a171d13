//! A seeded random pile of boxes for timing the collision stages: sizes 0.2 to 1.2 m in a cube
//! sized so that each box overlaps about three others, 10 % static, the rest moving.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Cuboid, Pose, Rot, Vec3, nalgebra::Translation3};
use tumble_gpu::layout::{GpuPose, GpuShape, GpuVelocity};

/// Poses, velocities and shapes of `n` boxes.
pub fn random_pile(n: usize, seed: u64) -> (Vec<GpuPose>, Vec<GpuVelocity>, Vec<GpuShape>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // 1.3 m of room per box along each axis: about three overlaps per box.
    let side = 1.3 * (n as f32).cbrt();
    let mut out = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..n {
        let is_static = rng.random_bool(0.1);
        let h = Vec3::from_fn(|_, _| rng.random_range(0.1..0.6));
        let t = Vec3::from_fn(|_, _| rng.random_range(0.0..side));
        let r = Rot::from_euler_angles(
            rng.random_range(-3.2..3.2),
            rng.random_range(-1.6..1.6),
            rng.random_range(-3.2..3.2),
        );
        let v = if is_static {
            GpuVelocity::default()
        } else {
            GpuVelocity::new(
                Vec3::from_fn(|_, _| rng.random_range(-2.0..2.0)),
                Vec3::from_fn(|_, _| rng.random_range(-2.0..2.0)),
            )
        };
        out.0.push(GpuPose::from_pose(&Pose::from_parts(
            Translation3::from(t),
            r,
        )));
        out.1.push(v);
        out.2.push(GpuShape::cuboid(&Cuboid::new(h), is_static));
    }
    out
}
