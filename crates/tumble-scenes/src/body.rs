//! One rigid box of a scene: its kind, size, initial state and material.

use serde::{Deserialize, Serialize};
use tumble_geometry::nalgebra::{Quaternion, Translation3};
use tumble_geometry::{Cuboid, Pose, Real, Rot, Vec3};

/// How a body moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum BodyKind {
    /// Never moves; infinite mass (floors, walls, ramps).
    Fixed,
    /// Moved by gravity and contacts.
    #[default]
    Dynamic,
    /// Moves with its given velocity, unaffected by contacts; infinite mass.
    Kinematic,
}

/// Default density in kg/m^3: a unit cube weighs 1 kg, so masses read as counts.
pub const DEFAULT_DENSITY: Real = 1.0;
/// Default friction coefficient: a dry, grippy contact (wood on wood is about 0.4 to 0.6).
pub const DEFAULT_FRICTION: Real = 0.6;
/// Default restitution: perfectly inelastic, so resting scenes do not bounce.
pub const DEFAULT_RESTITUTION: Real = 0.0;

/// One box of a scene.
///
/// Materials of a touching pair combine as Box2D and the thesis's successors do: friction is
/// the geometric mean `sqrt(mu_a * mu_b)` (either surface at zero makes the contact frictionless)
/// and restitution is the maximum (either bouncy surface bounces). The rapier builder sets
/// rapier's `GeometricMean` and `Max` combine rules to match.
///
/// Fields the schema does not know are refused, so a misspelt one is an error naming it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Fixed, dynamic or kinematic.
    #[serde(default)]
    pub kind: BodyKind,
    /// Half the box's size along its local axes, in meters (all positive).
    pub half_extents: [Real; 3],
    /// Initial centre, in meters.
    pub position: [Real; 3],
    /// Initial orientation as a unit quaternion `[x, y, z, w]`.
    #[serde(default = "identity_rotation")]
    pub rotation: [Real; 4],
    /// Initial velocity of the centre, in m/s.
    #[serde(default)]
    pub linear_velocity: [Real; 3],
    /// Initial angular velocity in world axes, in rad/s.
    #[serde(default)]
    pub angular_velocity: [Real; 3],
    /// Mass per volume in kg/m^3 (ignored for fixed and kinematic bodies).
    #[serde(default = "default_density")]
    pub density: Real,
    /// Coulomb friction coefficient (>= 0).
    #[serde(default = "default_friction")]
    pub friction: Real,
    /// Coefficient of restitution in `[0, 1]`.
    #[serde(default)]
    pub restitution: Real,
}

fn identity_rotation() -> [Real; 4] {
    [0.0, 0.0, 0.0, 1.0]
}

fn default_density() -> Real {
    DEFAULT_DENSITY
}

fn default_friction() -> Real {
    DEFAULT_FRICTION
}

impl BodySpec {
    /// A body of `kind` with default material, at rest, unrotated.
    pub fn new(kind: BodyKind, half_extents: [Real; 3], position: [Real; 3]) -> Self {
        Self {
            kind,
            half_extents,
            position,
            rotation: identity_rotation(),
            linear_velocity: [0.0; 3],
            angular_velocity: [0.0; 3],
            density: DEFAULT_DENSITY,
            friction: DEFAULT_FRICTION,
            restitution: DEFAULT_RESTITUTION,
        }
    }

    /// A dynamic box with default material.
    pub fn dynamic(half_extents: [Real; 3], position: [Real; 3]) -> Self {
        Self::new(BodyKind::Dynamic, half_extents, position)
    }

    /// A fixed box with default material.
    pub fn fixed(half_extents: [Real; 3], position: [Real; 3]) -> Self {
        Self::new(BodyKind::Fixed, half_extents, position)
    }

    /// A kinematic box with default material.
    pub fn kinematic(half_extents: [Real; 3], position: [Real; 3]) -> Self {
        Self::new(BodyKind::Kinematic, half_extents, position)
    }

    /// Sets the orientation from a quaternion `[x, y, z, w]`.
    pub fn with_rotation(mut self, rotation: [Real; 4]) -> Self {
        self.rotation = rotation;
        self
    }

    /// Sets the orientation as `angle` radians about the unit `axis`.
    pub fn with_axis_angle(self, axis: [Real; 3], angle: Real) -> Self {
        let q = Rot::from_scaled_axis(Vec3::from(axis).normalize() * angle);
        self.with_rotation([q.i, q.j, q.k, q.w])
    }

    /// Sets the initial linear velocity.
    pub fn with_linear_velocity(mut self, v: [Real; 3]) -> Self {
        self.linear_velocity = v;
        self
    }

    /// Sets the initial angular velocity (world axes).
    pub fn with_angular_velocity(mut self, w: [Real; 3]) -> Self {
        self.angular_velocity = w;
        self
    }

    /// Sets the density.
    pub fn with_density(mut self, density: Real) -> Self {
        self.density = density;
        self
    }

    /// Sets the friction coefficient.
    pub fn with_friction(mut self, friction: Real) -> Self {
        self.friction = friction;
        self
    }

    /// Sets the restitution coefficient.
    pub fn with_restitution(mut self, restitution: Real) -> Self {
        self.restitution = restitution;
        self
    }

    /// True for dynamic bodies.
    pub fn is_dynamic(&self) -> bool {
        self.kind == BodyKind::Dynamic
    }

    /// The collider shape.
    pub fn cuboid(&self) -> Cuboid {
        Cuboid::new(Vec3::from(self.half_extents))
    }

    /// The initial pose (the quaternion is normalized, so a slightly denormal one is accepted).
    pub fn pose(&self) -> Pose {
        let [x, y, z, w] = self.rotation;
        let rot = Rot::new_normalize(Quaternion::new(w, x, y, z));
        Pose::from_parts(Translation3::from(Vec3::from(self.position)), rot)
    }

    /// Volume in m^3.
    pub fn volume(&self) -> Real {
        self.cuboid().volume()
    }

    /// Mass in kg: `density * volume` for dynamic bodies, infinite for the others.
    pub fn mass(&self) -> Real {
        if self.is_dynamic() {
            self.density * self.volume()
        } else {
            Real::INFINITY
        }
    }
}
