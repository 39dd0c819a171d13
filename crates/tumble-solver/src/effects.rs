//! Which optional parts of the step a scene needs. A part that is off is not run at all; for a
//! scene that does not use it, skipping it changes only the time, never a result bit.

use tumble_geometry::Vec3;

use crate::{Body, BodyKind};

/// The optional effects of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Effects {
    /// Gravity in the velocity integration (unused under zero gravity).
    pub gravity: bool,
    /// The two friction rows per contact point (unused when no two bodies are both rough,
    /// since the combined friction `sqrt(mu_a mu_b)` is then zero).
    pub friction: bool,
    /// The restitution pass (unused when no material bounces).
    pub restitution: bool,
    /// Angular motion: gyroscopic term, angular damping, the angular velocity update, and
    /// torque from contacts; off, no body turns (zero inverse inertia and spin for the step, on
    /// the CPU as on the GPU). Unused when every moving body is dynamic with all rotations
    /// locked.
    pub rotation: bool,
    /// Kinematic bodies (unused when there are none): their wake checks in the sleep stage.
    pub kinematic: bool,
    /// Islands and sleep. Unlike the others, sleeping changes results (a sleeping body stops
    /// integrating), so it is never derived from the bodies: it is on only when asked for.
    pub sleep: bool,
}

impl Effects {
    /// Every effect on: the general step.
    pub const ALL: Self = Self {
        gravity: true,
        friction: true,
        restitution: true,
        rotation: true,
        kinematic: true,
        sleep: true,
    };

    /// The effects `bodies` under `gravity` can need (sleep off).
    pub fn of_bodies(bodies: &[Body], gravity: &Vec3) -> Self {
        let rough = bodies.iter().filter(|b| b.material.friction > 0.0).count();
        Self {
            gravity: *gravity != Vec3::zeros(),
            friction: rough >= 2,
            restitution: bodies.iter().any(|b| b.material.restitution > 0.0),
            // Kinematic bodies turn with whatever angular velocity they are given.
            rotation: bodies.iter().any(|b| match b.kind {
                BodyKind::Fixed => false,
                BodyKind::Kinematic => true,
                BodyKind::Dynamic => !b.locks.all_rotations(),
            }),
            kinematic: bodies.iter().any(|b| b.kind == BodyKind::Kinematic),
            sleep: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_geometry::Pose;

    fn body(kind: BodyKind, friction: f32, restitution: f32) -> Body {
        let material = crate::tests::material(friction, restitution);
        crate::tests::cube(kind, Pose::identity(), material)
    }

    #[test]
    fn a_single_rough_body_cannot_make_a_rough_contact() {
        let g = Vec3::new(0.0, -9.81, 0.0);
        let one = [
            body(BodyKind::Fixed, 0.6, 0.0),
            body(BodyKind::Dynamic, 0.0, 0.0),
        ];
        assert!(!Effects::of_bodies(&one, &g).friction);
        let two = [
            body(BodyKind::Fixed, 0.6, 0.0),
            body(BodyKind::Dynamic, 0.1, 0.0),
        ];
        assert!(Effects::of_bodies(&two, &g).friction);
    }

    #[test]
    fn effects_follow_materials_kinds_locks_and_gravity() {
        let mut locked = body(BodyKind::Dynamic, 0.0, 0.0);
        locked.locks.rotation = [true; 3];
        let scene = [body(BodyKind::Fixed, 0.0, 0.0), locked];
        let e = Effects::of_bodies(&scene, &Vec3::zeros());
        assert!(!e.gravity && !e.friction && !e.restitution && !e.rotation && !e.kinematic);
        assert!(!e.sleep, "sleep is never derived");
        let scene = [body(BodyKind::Kinematic, 0.0, 0.5), locked];
        let e = Effects::of_bodies(&scene, &Vec3::new(0.0, -1.0, 0.0));
        assert!(e.gravity && e.restitution && e.rotation && e.kinematic);
    }
}
