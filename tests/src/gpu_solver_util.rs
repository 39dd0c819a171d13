//! Small helpers shared by the GPU tests (`gpu_solver.rs`, `gpu_solver_motion.rs`,
//! `gpu_sleep`, `gpu_determinism.rs`, `gpu_wide_effects.rs`).

use tumble_geometry::{Cuboid, Pose, Real, Vec3};
use tumble_gpu::layout::{GpuPose, GpuVelocity};
use tumble_solver::{Body, BodyKind, Material};

/// The tests' step, s (60 Hz).
pub const DT: Real = 1.0 / 60.0;

/// A unit cube of `kind` at `position`.
pub fn cube(kind: BodyKind, position: Vec3) -> Body {
    Body::new(
        kind,
        Cuboid::new(Vec3::repeat(0.5)),
        Pose::new(position, Vec3::zeros()),
        1.0,
        Material::default(),
    )
    .unwrap()
}

/// A fixed 40 x 1 x 40 m floor whose top is y = 0, of `material`.
pub fn floor(material: Material) -> Body {
    Body::new(
        BodyKind::Fixed,
        Cuboid::new(Vec3::new(20.0, 0.5, 20.0)),
        Pose::translation(0.0, -0.5, 0.0),
        1.0,
        material,
    )
    .unwrap()
}

/// Every bit of `parts`, in order, for bitwise comparisons.
fn bits(parts: &[&[f32]]) -> Vec<u32> {
    parts
        .iter()
        .flat_map(|p| p.iter().map(|c| c.to_bits()))
        .collect()
}

/// Every bit of a GPU pose (position, then rotation), for bitwise comparisons.
pub fn pose_bits(p: &GpuPose) -> Vec<u32> {
    bits(&[&p.position, &p.rotation])
}

/// Every bit of a GPU velocity (linear, then angular), for bitwise comparisons.
pub fn velocity_bits(v: &GpuVelocity) -> Vec<u32> {
    bits(&[&v.linear, &v.angular])
}

/// Earth gravity along -y, m/s^2.
pub fn gravity() -> Vec3 {
    Vec3::new(0.0, -9.81, 0.0)
}

/// `|a - b| <= abs + rel * scale`, per component, with a message.
pub fn assert_close(what: &str, a: &[f32], b: &[f32], abs: f32, rel: f32, scale: f32) {
    // `zip` stops at the shorter slice: without this, a missing tail would pass unchecked.
    assert_eq!(
        a.len(),
        b.len(),
        "{what}: gpu has {} values, cpu {}",
        a.len(),
        b.len()
    );
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= abs + rel * scale,
            "{what}[{i}]: gpu {x} vs cpu {y} (tolerance {abs} + {rel} x {scale})"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn assert_close_passes_within_the_tolerance() {
        // 1e-3 apart, tolerance 1e-4 + 0.01 x 1.0.
        assert_close("v", &[1.0, 2.0], &[1.001, 2.0], 1e-4, 0.01, 1.0);
    }

    #[test]
    #[should_panic(expected = "v[1]: gpu 2.1 vs cpu 2")]
    fn assert_close_fails_outside_the_tolerance() {
        assert_close("v", &[1.0, 2.1], &[1.0, 2.0], 1e-4, 0.01, 1.0);
    }

    #[test]
    #[should_panic(expected = "v: gpu has 2 values, cpu 3")]
    fn assert_close_fails_on_a_missing_tail() {
        // The first two values agree: only the length check can catch the missing third.
        assert_close("v", &[1.0, 2.0], &[1.0, 2.0, 3.0], 1e-4, 0.0, 0.0);
    }
}
