//! Tumble's geometry layer: math aliases over nalgebra, the cuboid collider, axis-aligned
//! bounding boxes, planes, polygon clipping, segment closest points, contact reduction, the
//! contact manifold types every later stage (CPU and GPU) shares, and the queries on boxes
//! (ray casts, point projection, box-box overlap and box casts).
//!
//! ```
//! use tumble_geometry::{Cuboid, Pose, Rot, Vec3};
//!
//! // A 1 m cube turned 45 degrees about y: its bounding box widens to the diagonal.
//! let cube = Cuboid::new(Vec3::repeat(0.5));
//! let pose = Pose::from_parts(
//!     Vec3::new(0.0, 2.0, 0.0).into(),
//!     Rot::from_axis_angle(&Vec3::y_axis(), std::f32::consts::FRAC_PI_4),
//! );
//! let aabb = cube.aabb(&pose, 0.0);
//! let half_diagonal = 0.5 * std::f32::consts::SQRT_2;
//! assert!((aabb.max.x - half_diagonal).abs() < 1e-5);
//! assert!((aabb.max.y - 2.5).abs() < 1e-5, "height unchanged by a turn about y");
//! assert!((cube.volume() - 1.0).abs() < 1e-6);
//! ```
#![warn(missing_docs)]

mod aabb;
mod clip;
mod cuboid;
mod manifold;
mod math;
mod plane;
mod ray;
mod reduce;
mod segment;
mod sweep;
#[cfg(test)]
mod test_support;

pub use aabb::Aabb;
pub use clip::{ClipPolygon, ClipVertex, MAX_CLIP_VERTICES};
pub use cuboid::{CUBOID_EDGES, CUBOID_FACES, Cuboid, CuboidFace};
pub use manifold::{ContactPoint, FeatureKind, MAX_MANIFOLD_POINTS, Manifold};
pub use math::{Mat3, Point3, Pose, Real, Rot, Vec3};
pub use plane::{Plane, signed_distance_to_plane};
pub use ray::{CastHit, PointProjection};
pub use reduce::{reduce_into, select_four};
pub use segment::{
    DEGENERATE_LENGTH_RATIO as SEGMENT_DEGENERATE_RATIO,
    PARALLEL_SIN_SQ as SEGMENT_PARALLEL_SIN_SQ, SegmentClosestPoints, closest_points_segments,
};
pub use sweep::{PARALLEL_AXIS_NORM_SQ, cast_cuboid, cuboids_intersect};

/// Re-export of the math crate, so users need one import.
pub use nalgebra;

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
