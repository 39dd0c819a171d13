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

/// Declares builder methods that each set one field to their argument and return the
/// description: `name(arg: Type) => field.path;`, each with its doc comment.
macro_rules! setters {
    ($($(#[$meta:meta])* $name:ident($arg:ident: $ty:ty) => $($field:ident).+;)*) => {
        $(
            $(#[$meta])*
            pub fn $name(mut self, $arg: $ty) -> Self {
                self.$($field).+ = $arg;
                self
            }
        )*
    };
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

    setters! {
        /// The box's half extents.
        cuboid(half_extents: Vec3) => half_extents;
        /// The initial pose.
        pose(pose: Pose) => pose;
    }

    /// The initial position (keeps the rotation).
    pub fn translation(mut self, x: Real, y: Real, z: Real) -> Self {
        self.pose.translation.vector = Vec3::new(x, y, z);
        self
    }

    setters! {
        /// Density in kg/m^3.
        density(density: Real) => density;
        /// Coulomb friction coefficient.
        friction(friction: Real) => material.friction;
        /// Coefficient of restitution in `[0, 1]`.
        restitution(restitution: Real) => material.restitution;
        /// Initial linear velocity.
        linear_velocity(v: Vec3) => linear_velocity;
        /// Initial angular velocity (world axes).
        angular_velocity(w: Vec3) => angular_velocity;
    }

    /// Locks rotation about all three axes.
    pub fn lock_rotations(mut self) -> Self {
        self.locks.rotation = [true; 3];
        self
    }

    setters! {
        /// Locks rotation about the world axes flagged `true`.
        lock_rotation_axes(axes: [bool; 3]) => locks.rotation;
        /// Locks translation along the world axes flagged `true`.
        lock_translations(axes: [bool; 3]) => locks.translation;
        /// Linear damping rate, 1/s.
        linear_damping(rate: Real) => linear_damping;
        /// Angular damping rate, 1/s.
        angular_damping(rate: Real) => angular_damping;
        /// Which bodies this one may collide with: see [`CollisionGroups`] (two bodies collide
        /// only when each one's memberships meet the other's filter).
        collision_groups(groups: CollisionGroups) => collision_groups;
        /// The multiple of the world's gravity acting on the body: 0 floats, 2 falls twice as
        /// fast, -1 rises; within `[-10, 10]` (`bounds::MAX_GRAVITY_SCALE`).
        gravity_scale(scale: Real) => gravity_scale;
        /// A value kept with the body for the caller, never read by the physics
        /// ([`crate::World::user_data`]).
        user_data(data: u128) => user_data;
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
