//! A body's state as an engine reports it, in the scene's plain-array convention.

use tumble_geometry::Real;
use tumble_geometry::nalgebra::{Quaternion, Translation3};
use tumble_geometry::{Pose, Rot, Vec3};

use crate::BodySpec;

/// One body's pose and velocity at one instant (world frame, quaternion `[x, y, z, w]`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyState {
    /// Centre, in meters.
    pub position: [Real; 3],
    /// Orientation as a unit quaternion `[x, y, z, w]`.
    pub rotation: [Real; 4],
    /// Velocity of the centre, m/s.
    pub linear_velocity: [Real; 3],
    /// Angular velocity in world axes, rad/s.
    pub angular_velocity: [Real; 3],
}

impl BodyState {
    /// The state a scene body starts in.
    pub fn initial(spec: &BodySpec) -> Self {
        Self {
            position: spec.position,
            rotation: spec.rotation,
            linear_velocity: spec.linear_velocity,
            angular_velocity: spec.angular_velocity,
        }
    }

    /// The orientation (normalized).
    pub fn rot(&self) -> Rot {
        let [x, y, z, w] = self.rotation;
        Rot::new_normalize(Quaternion::new(w, x, y, z))
    }

    /// The pose.
    pub fn pose(&self) -> Pose {
        Pose::from_parts(Translation3::from(Vec3::from(self.position)), self.rot())
    }

    /// True when every component is finite.
    pub fn is_finite(&self) -> bool {
        self.position
            .iter()
            .chain(&self.rotation)
            .chain(&self.linear_velocity)
            .chain(&self.angular_velocity)
            .all(|c| c.is_finite())
    }
}
