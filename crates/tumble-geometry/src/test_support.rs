//! Shapes and poses the unit tests of several modules share.

use crate::{Cuboid, Pose, Real, Rot, Vec3, nalgebra};

/// The box of half extents 1 x 2 x 3 the shape tests measure against.
pub(crate) fn brick() -> Cuboid {
    Cuboid::new(Vec3::new(1.0, 2.0, 3.0))
}

/// The pose at `(x, y, z)` turned by `angle` about z (a quarter turn maps local +x to world
/// +y and local +y to world -x).
pub(crate) fn turned_about_z(x: Real, y: Real, z: Real, angle: Real) -> Pose {
    Pose::from_parts(
        nalgebra::Translation3::new(x, y, z),
        Rot::from_axis_angle(&Vec3::z_axis(), angle),
    )
}
