//! The builder users describe a body with before adding it to a world.

use tumble_geometry::{Cuboid, Pose, Real, Vec3};
use tumble_solver::{Body, BodyKind, BodyState, CollisionGroups, Locks, Material, bounds};

use crate::{Error, WorldConfig};

/// Half extents of a body when none are given: a 1 m cube.
pub const DEFAULT_HALF_EXTENTS: Real = 0.5;

/// Everything needed to create a body; build with [`BodyDesc::dynamic`], [`BodyDesc::fixed`]
/// or [`BodyDesc::kinematic`] and the chained setters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyDesc {
    /// Fixed, dynamic or kinematic.
    pub kind: BodyKind,
    /// Half the box size along its local axes, m.
    pub half_extents: Vec3,
    /// Initial pose of the box centre.
    pub pose: Pose,
    /// Density in kg/m^3 (sets the mass of dynamic bodies).
    pub density: Real,
    /// Surface friction and restitution.
    pub material: Material,
    /// Initial linear velocity, m/s (ignored for fixed bodies).
    pub linear_velocity: Vec3,
    /// Initial angular velocity in world axes, rad/s (ignored for fixed bodies).
    pub angular_velocity: Vec3,
    /// Per-axis locks (world axes).
    pub locks: Locks,
    /// Linear damping rate, 1/s.
    pub linear_damping: Real,
    /// Angular damping rate, 1/s.
    pub angular_damping: Real,
    /// Which bodies this one may collide with ([`CollisionGroups::ALL`] by default).
    pub collision_groups: CollisionGroups,
    /// The multiple of the world's gravity acting on the body (1 by default).
    pub gravity_scale: Real,
    /// A value kept for the caller (an entity id, an index), never read by the physics.
    pub user_data: u128,
}

impl BodyDesc {
    fn new(kind: BodyKind) -> Self {
        Self {
            kind,
            half_extents: Vec3::repeat(DEFAULT_HALF_EXTENTS),
            pose: Pose::identity(),
            density: 1.0,
            material: Material::default(),
            linear_velocity: Vec3::zeros(),
            angular_velocity: Vec3::zeros(),
            locks: Locks::default(),
            linear_damping: 0.0,
            angular_damping: 0.0,
            collision_groups: CollisionGroups::ALL,
            gravity_scale: 1.0,
            user_data: 0,
        }
    }

    /// A body moved by gravity and contacts.
    pub fn dynamic() -> Self {
        Self::new(BodyKind::Dynamic)
    }

    /// A body that never moves.
    pub fn fixed() -> Self {
        Self::new(BodyKind::Fixed)
    }

    /// A body that moves with the velocity the user gives it and pushes dynamic bodies.
    pub fn kinematic() -> Self {
        Self::new(BodyKind::Kinematic)
    }

    /// The box's half extents.
    pub fn cuboid(mut self, half_extents: Vec3) -> Self {
        self.half_extents = half_extents;
        self
    }

    /// The initial pose.
    pub fn pose(mut self, pose: Pose) -> Self {
        self.pose = pose;
        self
    }

    /// The initial position (keeps the rotation).
    pub fn translation(mut self, x: Real, y: Real, z: Real) -> Self {
        self.pose.translation.vector = Vec3::new(x, y, z);
        self
    }

    /// Density in kg/m^3.
    pub fn density(mut self, density: Real) -> Self {
        self.density = density;
        self
    }

    /// Coulomb friction coefficient.
    pub fn friction(mut self, friction: Real) -> Self {
        self.material.friction = friction;
        self
    }

    /// Coefficient of restitution in `[0, 1]`.
    pub fn restitution(mut self, restitution: Real) -> Self {
        self.material.restitution = restitution;
        self
    }

    /// Initial linear velocity.
    pub fn linear_velocity(mut self, v: Vec3) -> Self {
        self.linear_velocity = v;
        self
    }

    /// Initial angular velocity (world axes).
    pub fn angular_velocity(mut self, w: Vec3) -> Self {
        self.angular_velocity = w;
        self
    }

    /// Locks rotation about all three axes.
    pub fn lock_rotations(mut self) -> Self {
        self.locks.rotation = [true; 3];
        self
    }

    /// Locks rotation about the world axes flagged `true`.
    pub fn lock_rotation_axes(mut self, axes: [bool; 3]) -> Self {
        self.locks.rotation = axes;
        self
    }

    /// Locks translation along the world axes flagged `true`.
    pub fn lock_translations(mut self, axes: [bool; 3]) -> Self {
        self.locks.translation = axes;
        self
    }

    /// Linear damping rate, 1/s.
    pub fn linear_damping(mut self, rate: Real) -> Self {
        self.linear_damping = rate;
        self
    }

    /// Angular damping rate, 1/s.
    pub fn angular_damping(mut self, rate: Real) -> Self {
        self.angular_damping = rate;
        self
    }

    /// Which bodies this one may collide with: see [`CollisionGroups`] (two bodies collide
    /// only when each one's memberships meet the other's filter).
    pub fn collision_groups(mut self, groups: CollisionGroups) -> Self {
        self.collision_groups = groups;
        self
    }

    /// The multiple of the world's gravity acting on the body: 0 floats, 2 falls twice as
    /// fast, -1 rises; within `[-10, 10]` (`bounds::MAX_GRAVITY_SCALE`).
    pub fn gravity_scale(mut self, scale: Real) -> Self {
        self.gravity_scale = scale;
        self
    }

    /// A value kept with the body for the caller, never read by the physics
    /// ([`crate::World::user_data`]).
    pub fn user_data(mut self, data: u128) -> Self {
        self.user_data = data;
        self
    }

    /// Validates every field against its range (`tumble_solver::bounds`; the angular speed
    /// against the fastest spin `config`'s substeps carry) and builds the solver's body and
    /// its initial state.
    pub(crate) fn build(&self, config: &WorldConfig) -> Result<(Body, BodyState), Error> {
        let mut body = Body::new(
            self.kind,
            Cuboid::new(self.half_extents),
            self.pose,
            self.density,
            self.material,
        )?;
        bounds::require_linear_speed("linear_velocity", &self.linear_velocity)?;
        bounds::require_angular_speed(
            "angular_velocity",
            &self.angular_velocity,
            config.dt,
            config.solver.substeps,
        )?;
        bounds::require_damping("linear_damping", self.linear_damping)?;
        bounds::require_damping("angular_damping", self.angular_damping)?;
        bounds::require_gravity_scale(self.gravity_scale)?;
        body.locks = self.locks;
        body.groups = self.collision_groups;
        body.gravity_scale = self.gravity_scale;
        body.linear_damping = self.linear_damping;
        body.angular_damping = self.angular_damping;
        let state = match self.kind {
            BodyKind::Fixed => BodyState::default(),
            BodyKind::Dynamic | BodyKind::Kinematic => BodyState::moving(
                self.linear_velocity
                    .component_mul(&self.locks.translation_mask()),
                self.angular_velocity
                    .component_mul(&self.locks.rotation_mask()),
            ),
        };
        // Normalize the rotation so a slightly off quaternion from user data does not scale
        // the box.
        body.pose.rotation.renormalize();
        Ok((body, state))
    }
}
