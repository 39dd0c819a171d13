//! Tumble's geometry layer: math aliases over nalgebra, the cuboid collider, axis-aligned
//! bounding boxes, planes, polygon clipping, segment closest points, contact reduction, and the
//! contact manifold types every later stage (CPU and GPU) shares.
#![warn(missing_docs)]

mod aabb;
mod clip;
mod cuboid;
mod manifold;
mod math;
mod plane;
mod reduce;
mod segment;

pub use aabb::Aabb;
pub use clip::{ClipPolygon, ClipVertex, MAX_CLIP_VERTICES};
pub use cuboid::{CUBOID_EDGES, CUBOID_FACES, Cuboid, CuboidFace};
pub use manifold::{ContactPoint, FeatureKind, MAX_MANIFOLD_POINTS, Manifold};
pub use math::{Mat3, Point3, Pose, Real, Rot, Vec3};
pub use plane::{Plane, signed_distance_to_plane};
pub use reduce::{reduce_into, select_four};
pub use segment::{
    DEGENERATE_LENGTH_RATIO as SEGMENT_DEGENERATE_RATIO,
    PARALLEL_SIN_SQ as SEGMENT_PARALLEL_SIN_SQ, SegmentClosestPoints, closest_points_segments,
};

/// Re-export of the math crate, so users need one import.
pub use nalgebra;
