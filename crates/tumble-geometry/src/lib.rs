//! Tumble's geometry layer: math aliases over nalgebra, the cuboid collider, axis-aligned
//! bounding boxes, and the contact manifold types every later stage (CPU and GPU) shares.
#![warn(missing_docs)]

mod aabb;
mod cuboid;
mod manifold;
mod math;

pub use aabb::Aabb;
pub use cuboid::{CUBOID_EDGES, CUBOID_FACES, Cuboid, CuboidFace};
pub use manifold::{ContactPoint, FeatureKind, MAX_MANIFOLD_POINTS, Manifold};
pub use math::{Point3, Pose, Real, Rot, Vec3};

/// Re-export of the math crate, so users need one import.
pub use nalgebra;
