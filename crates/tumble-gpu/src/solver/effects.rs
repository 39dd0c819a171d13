//! Effects a scene does not use are compiled out of the solver pipelines through WGSL
//! `override` switches, never branched on per thread. Turning an effect off only removes work
//! whose result is known to be zero, so results do not change.

use tumble_geometry::Vec3;
use tumble_solver::{Body, BodyKind};

/// Which optional parts of the solver the pipelines contain.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Effects {
    /// Friction rows (off when no contact can have a nonzero combined friction).
    pub friction: bool,
    /// The restitution pass (off when no material bounces).
    pub restitution: bool,
    /// Gravity in the velocity integration (off for zero gravity).
    pub gravity: bool,
    /// Angular terms (off when every moving body is dynamic with all rotations locked).
    pub rotation: bool,
}

impl Effects {
    /// Everything compiled in.
    pub const ALL: Self = Self {
        friction: true,
        restitution: true,
        gravity: true,
        rotation: true,
    };

    /// The effects `bodies` under `gravity` can need.
    pub fn of_scene(bodies: &[Body], gravity: &Vec3) -> Self {
        // Combined friction is sqrt(mu_a mu_b): nonzero only between two rough bodies.
        let rough = bodies.iter().filter(|b| b.material.friction > 0.0).count();
        Self {
            friction: rough >= 2,
            restitution: bodies.iter().any(|b| b.material.restitution > 0.0),
            gravity: *gravity != Vec3::zeros(),
            // Kinematic bodies turn with whatever angular velocity they are given.
            rotation: bodies.iter().any(|b| match b.kind {
                BodyKind::Fixed => false,
                BodyKind::Kinematic => true,
                BodyKind::Dynamic => !b.locks.all_rotations(),
            }),
        }
    }

    /// The `override` values of the switches.
    pub fn overrides(&self) -> [(&'static str, f64); 4] {
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        [
            ("ENABLE_FRICTION", flag(self.friction)),
            ("ENABLE_RESTITUTION", flag(self.restitution)),
            ("ENABLE_GRAVITY", flag(self.gravity)),
            ("ENABLE_ROTATION", flag(self.rotation)),
        ]
    }
}
