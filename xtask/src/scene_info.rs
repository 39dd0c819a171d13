//! What the metrics need to know about a scene's bodies: size, mass, inertia and rest pose.

use tumble_geometry::{Pose, Real, Vec3};

/// One body, as the metrics see it.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyInfo {
    /// True for bodies moved by gravity and contacts.
    pub dynamic: bool,
    /// Half the box's size along its local axes, in meters.
    pub half_extents: Vec3,
    /// Mass in kg (only meaningful for dynamic bodies).
    pub mass: Real,
    /// Principal moments of inertia about the local axes, in kg m^2.
    pub inertia: Vec3,
    /// The pose the body starts in, which is where a resting scene should keep it.
    pub rest_pose: Pose,
}

impl BodyInfo {
    /// A box of `half_extents` and `mass` starting at `rest_pose`; its inertia is the solid
    /// cuboid's, `m (b^2 + c^2) / 3` about each axis with `b`, `c` the other two half extents.
    pub fn cuboid(dynamic: bool, half_extents: Vec3, mass: Real, rest_pose: Pose) -> Self {
        let h2 = half_extents.component_mul(&half_extents);
        let third = mass / 3.0;
        let inertia = Vec3::new(
            third * (h2.y + h2.z),
            third * (h2.x + h2.z),
            third * (h2.x + h2.y),
        );
        Self {
            dynamic,
            half_extents,
            mass,
            inertia,
            rest_pose,
        }
    }

    /// Radius of the sphere around the centre that holds the whole box: a bound on how far
    /// any point of the body is from its centre, used to turn spin into point speed.
    pub fn bounding_radius(&self) -> Real {
        self.half_extents.norm()
    }

    /// Half the body's extent along the unit direction `dir` when at `pose`.
    pub fn half_extent_along(&self, pose: &Pose, dir: &Vec3) -> Real {
        let local = pose.rotation.inverse_transform_vector(dir);
        local.abs().dot(&self.half_extents)
    }
}

/// A scene as the validation measures it.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneInfo {
    /// The scene's name.
    pub name: String,
    /// Every body, in the order engines report states.
    pub bodies: Vec<BodyInfo>,
    /// Gravity acceleration, in m/s^2.
    pub gravity: Vec3,
    /// Fixed time step, in seconds.
    pub dt: Real,
}

impl SceneInfo {
    /// The unit "up" direction (against gravity), or +y in a scene without gravity.
    pub fn up(&self) -> Vec3 {
        self.gravity
            .try_normalize(Real::EPSILON)
            .map_or(Vec3::y(), |g| -g)
    }
}
