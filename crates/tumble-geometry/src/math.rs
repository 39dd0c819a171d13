//! Scalar and vector aliases: the engine computes in `f32` everywhere.

/// The engine's scalar: `f32`, on the CPU as on the GPU.
pub type Real = f32;
/// A 3D vector (directions, velocities, half extents).
pub type Vec3 = nalgebra::Vector3<Real>;
/// A 3D point (positions).
pub type Point3 = nalgebra::Point3<Real>;
/// A rigid pose: rotation then translation.
pub type Pose = nalgebra::Isometry3<Real>;
/// A unit quaternion rotation.
pub type Rot = nalgebra::UnitQuaternion<Real>;
/// A 3x3 matrix (relative rotations between box frames).
pub type Mat3 = nalgebra::Matrix3<Real>;
