//! Bodies as the solver sees them: cold data (pose, mass, shape, material, locks) apart from
//! the hot state the constraint loops read and write (velocities and the in-step deltas).

use tumble_broad::CollisionGroups;
use tumble_geometry::{Cuboid, Pose, Real, Rot, Vec3};

use crate::{InvalidParameter, MassProperties, Mat3, Material, bounds};

/// How a body moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum BodyKind {
    /// Never moves; infinite mass.
    Fixed,
    /// Moved by gravity and contacts.
    Dynamic,
    /// Moves with the velocity the user sets; infinite mass, pushes dynamic bodies.
    Kinematic,
}

/// Per-axis locks in world axes: a locked axis neither translates nor rotates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Locks {
    /// Translation along world x, y, z is locked.
    pub translation: [bool; 3],
    /// Rotation about world x, y, z is locked.
    pub rotation: [bool; 3],
}

impl Locks {
    /// Multiplier per world axis for linear motion: 0 where locked, 1 where free.
    pub fn translation_mask(&self) -> Vec3 {
        Vec3::from_fn(|i, _| if self.translation[i] { 0.0 } else { 1.0 })
    }

    /// Multiplier per world axis for angular motion: 0 where locked, 1 where free.
    pub fn rotation_mask(&self) -> Vec3 {
        Vec3::from_fn(|i, _| if self.rotation[i] { 0.0 } else { 1.0 })
    }

    /// True when any rotation axis is locked.
    pub fn any_rotation(&self) -> bool {
        self.rotation.iter().any(|&l| l)
    }

    /// True when every rotation axis is locked: the body's constraint rows have no angular part.
    pub fn all_rotations(&self) -> bool {
        self.rotation.iter().all(|&l| l)
    }
}

/// The cold part of a body: read once per step to build constraints, written once at the end.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Body {
    /// Fixed, dynamic or kinematic.
    pub kind: BodyKind,
    /// Pose of the centre of mass at the start of the step (the box is centred on it).
    pub pose: Pose,
    /// The collision shape.
    pub shape: Cuboid,
    /// `1 / mass`; 0 for fixed and kinematic bodies.
    pub inverse_mass: Real,
    /// Inverse principal moments about the body's local axes; 0 for fixed and kinematic bodies.
    pub inverse_inertia_local: Vec3,
    /// Surface friction and restitution.
    pub material: Material,
    /// Per-axis locks of translation and rotation (world axes).
    pub locks: Locks,
    /// Linear damping rate in 1/s (velocity decays as `1 / (1 + h c)` per substep).
    pub linear_damping: Real,
    /// Angular damping rate in 1/s.
    pub angular_damping: Real,
    /// Which bodies this one may collide with (the broad phase's pair filter); every body by
    /// default.
    pub groups: CollisionGroups,
    /// Force at the centre of mass, N (world axes), applied to a dynamic body in every
    /// substep until changed; zero by default.
    pub force: Vec3,
    /// Torque, N m (world axes), applied to a dynamic body in every substep until changed;
    /// zero by default.
    pub torque: Vec3,
    /// The multiple of the world's gravity that acts on the body (1 by default; 0 floats,
    /// negative rises).
    pub gravity_scale: Real,
}

/// The hot part of a body: what the solver's inner loops touch (52 bytes on the CPU, in
/// this field order: the lane kernels load a state as thirteen consecutive floats).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BodyState {
    /// Linear velocity of the centre of mass, m/s (12 bytes).
    pub linear_velocity: Vec3,
    /// Angular velocity in world axes, rad/s (12 bytes).
    pub angular_velocity: Vec3,
    /// Translation accumulated since the start of the step (12 bytes). Using a delta position
    /// reduces round-off far from the origin: contact separations are computed from small
    /// deltas rather than from differences of large absolute coordinates.
    pub delta_position: Vec3,
    /// Rotation accumulated since the start of the step (16 bytes).
    pub delta_rotation: Rot,
}

impl Default for BodyState {
    fn default() -> Self {
        Self {
            linear_velocity: Vec3::zeros(),
            angular_velocity: Vec3::zeros(),
            delta_position: Vec3::zeros(),
            delta_rotation: Rot::identity(),
        }
    }
}

impl BodyState {
    /// A state moving with the given velocities and no accumulated delta.
    pub fn moving(linear_velocity: Vec3, angular_velocity: Vec3) -> Self {
        Self {
            linear_velocity,
            angular_velocity,
            ..Self::default()
        }
    }
}

impl Body {
    /// A body of `kind` and `shape` at `pose`; `density` sets the mass of dynamic bodies (it
    /// is still validated for the others, so a bad value is reported whatever the kind).
    /// Every quantity must lie within its range of [`crate::bounds`]: half extents, density,
    /// friction, and the centre's distance from the origin.
    pub fn new(
        kind: BodyKind,
        shape: Cuboid,
        pose: Pose,
        density: Real,
        material: Material,
    ) -> Result<Self, InvalidParameter> {
        bounds::require_half_extents(&shape.half_extents)?;
        bounds::require_density(density)?;
        let mass = MassProperties::cuboid(&shape, density)?;
        material.validate()?;
        bounds::require_in_range(
            "friction",
            material.friction,
            0.0,
            bounds::MAX_FRICTION,
            bounds::EXPECTED_FRICTION,
        )?;
        let pose_ok = pose.translation.vector.iter().all(|c| c.is_finite())
            && pose.rotation.coords.iter().all(|c| c.is_finite());
        if !pose_ok {
            return Err(InvalidParameter::new(
                "pose",
                pose,
                "finite translation and rotation",
            ));
        }
        bounds::require_pose("pose", &pose)?;
        let (inverse_mass, inverse_inertia_local) = match kind {
            BodyKind::Dynamic => (mass.inverse_mass(), mass.inverse_principal_inertia()),
            BodyKind::Fixed | BodyKind::Kinematic => (0.0, Vec3::zeros()),
        };
        Ok(Self {
            kind,
            pose,
            shape,
            inverse_mass,
            inverse_inertia_local,
            material,
            locks: Locks::default(),
            linear_damping: 0.0,
            angular_damping: 0.0,
            groups: CollisionGroups::ALL,
            force: Vec3::zeros(),
            torque: Vec3::zeros(),
            gravity_scale: 1.0,
        })
    }

    /// True when a force or a torque acts on the body.
    pub fn has_load(&self) -> bool {
        self.force != Vec3::zeros() || self.torque != Vec3::zeros()
    }

    /// True for dynamic bodies: the only ones contacts move.
    pub fn is_dynamic(&self) -> bool {
        self.kind == BodyKind::Dynamic
    }

    /// The inverse mass per world axis, zero on locked axes (the linear part of `M^-1`).
    pub fn inverse_mass_axes(&self) -> Vec3 {
        self.locks.translation_mask() * self.inverse_mass
    }

    /// The world-space inverse inertia `P R D R^T P`, with `D` the local inverse moments and
    /// `P` zeroing locked world rotation axes.
    pub fn inverse_inertia_world(&self) -> Mat3 {
        if self.locks.all_rotations() || self.inverse_inertia_local == Vec3::zeros() {
            return Mat3::zeros();
        }
        let r = self.pose.rotation.to_rotation_matrix().into_inner();
        let world = r * Mat3::from_diagonal(&self.inverse_inertia_local) * r.transpose();
        if self.locks.any_rotation() {
            let p = Mat3::from_diagonal(&self.locks.rotation_mask());
            p * world * p
        } else {
            world
        }
    }

    /// The principal moments (not inverted) in the local frame; zero for infinite inertia.
    pub fn inertia_local(&self) -> Vec3 {
        self.inverse_inertia_local
            .map(|i| if i > 0.0 { 1.0 / i } else { 0.0 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_geometry::nalgebra::{Translation3, UnitQuaternion};

    fn box_body(kind: BodyKind) -> Body {
        let pose = Pose::from_parts(
            Translation3::new(1.0, 2.0, 3.0),
            UnitQuaternion::from_euler_angles(0.3, -0.2, 0.7),
        );
        Body::new(
            kind,
            Cuboid::new(Vec3::new(0.5, 1.0, 1.5)),
            pose,
            2.0,
            Material::default(),
        )
        .unwrap()
    }

    #[test]
    fn world_inverse_inertia_inverts_the_rotated_inertia() {
        let b = box_body(BodyKind::Dynamic);
        let r = b.pose.rotation.to_rotation_matrix().into_inner();
        let inertia = r * Mat3::from_diagonal(&b.inertia_local()) * r.transpose();
        let product = b.inverse_inertia_world() * inertia;
        // I^-1 I = identity up to f32 round-off of two 3x3 products (~1e-6).
        assert!((product - Mat3::identity()).abs().max() < 1e-4, "{product}");
    }

    #[test]
    fn fixed_and_kinematic_bodies_have_infinite_mass() {
        for kind in [BodyKind::Fixed, BodyKind::Kinematic] {
            let b = box_body(kind);
            assert_eq!(b.inverse_mass, 0.0);
            assert_eq!(b.inverse_inertia_world(), Mat3::zeros());
        }
    }

    #[test]
    fn locked_axes_have_no_inverse_mass_or_inertia() {
        let mut b = box_body(BodyKind::Dynamic);
        b.locks.translation = [false, true, false];
        b.locks.rotation = [true, false, true];
        assert_eq!(b.inverse_mass_axes().y, 0.0);
        assert!(b.inverse_mass_axes().x > 0.0);
        let w = b.inverse_inertia_world();
        // Only the y-y entry survives when x and z rotations are locked.
        for (i, j) in [(0, 0), (0, 1), (2, 2), (1, 2), (0, 2)] {
            assert_eq!(w[(i, j)], 0.0);
        }
        assert!(w[(1, 1)] > 0.0);
    }

    #[test]
    fn non_finite_pose_is_rejected() {
        let pose = Pose::translation(Real::NAN, 0.0, 0.0);
        let e = Body::new(
            BodyKind::Dynamic,
            Cuboid::new(Vec3::repeat(0.5)),
            pose,
            1.0,
            Material::default(),
        )
        .unwrap_err();
        assert_eq!(e.field, "pose");
    }

    #[test]
    fn out_of_bound_bodies_are_rejected_by_field() {
        let make = |h: Real, density: Real, x: Real, friction: Real| {
            Body::new(
                BodyKind::Dynamic,
                Cuboid::new(Vec3::new(0.5, h, 0.5)),
                Pose::translation(x, 0.0, 0.0),
                density,
                Material {
                    friction,
                    restitution: 0.0,
                },
            )
        };
        make(0.5, 1.0, 0.0, 0.6).unwrap();
        // Each case is finite and positive, so only the bounds can refuse it.
        for (body, field) in [
            (make(1e-4, 1.0, 0.0, 0.6), "half_extents.y"),
            (make(2e3, 1.0, 0.0, 0.6), "half_extents.y"),
            (make(0.5, 1e-30, 0.0, 0.6), "density"),
            (make(0.5, 1e30, 0.0, 0.6), "density"),
            (make(0.5, 1.0, 1e6, 0.6), "pose"),
            (make(0.5, 1.0, 0.0, 1e30), "friction"),
        ] {
            assert_eq!(body.unwrap_err().field, field);
        }
    }
}
