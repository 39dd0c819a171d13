//! Small helpers shared by the GPU solver tests (`gpu_solver.rs`, `gpu_solver_motion.rs`).

use tumble_geometry::{Cuboid, Pose, Real, Vec3};
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

/// Earth gravity along -y, m/s^2.
pub fn gravity() -> Vec3 {
    Vec3::new(0.0, -9.81, 0.0)
}

/// `|a - b| <= abs + rel * scale`, per component, with a message.
pub fn assert_close(what: &str, a: &[f32], b: &[f32], abs: f32, rel: f32, scale: f32) {
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= abs + rel * scale,
            "{what}[{i}]: gpu {x} vs cpu {y} (tolerance {abs} + {rel} x {scale})"
        );
    }
}
