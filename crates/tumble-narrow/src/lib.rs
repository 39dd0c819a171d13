//! Tumble's narrow phase: box-box contact manifolds by the separating axis test, with
//! Sutherland-Hodgman clipping for face contacts, closest points for edge contacts, reduction
//! to four points, and feature ids that stay the same while the same features touch.
//!
//! The pipeline for one pair ([`collide_cuboids`]):
//! 1. [`BoxPair`]: B in A's frame (relative rotation, delta position);
//! 2. [`SatQuery`]: separations along A's 3 face normals, B's 3, and the 9 edge cross products;
//! 3. [`preferred_axis`]: the deepest axis, preferring A's face over B's and faces over edges
//!    within the tolerances of [`tolerance`], and last step's reference face (hysteresis);
//! 4. [`face_contact`] (clip the incident face against the reference side planes) or
//!    [`edge_contact`] (closest points of the two edges); apart but within the margin, the
//!    closest pair is checked and, when no SAT axis carries it, [`closest_vertex`] supplies it;
//! 5. reduction to four points ([`tumble_geometry::reduce_into`]).
//!
//! The same steps, with the same fixed arrays and indices, are what the GPU kernel runs.
//!
//! ```
//! use tumble_geometry::{Cuboid, Pose, Vec3};
//! use tumble_narrow::collide_cuboids;
//!
//! // Two unit cubes, B resting on A and sunk 1 cm into it.
//! let cube = Cuboid::new(Vec3::repeat(0.5));
//! let a = Pose::translation(0.0, 0.0, 0.0);
//! let b = Pose::translation(0.0, 0.99, 0.0);
//! let manifold = collide_cuboids(&cube, &a, &cube, &b, 0.0).expect("the cubes overlap");
//! // A face contact: the four corners of the shared square, pushing B up.
//! assert_eq!(manifold.len, 4);
//! assert!((manifold.normal - Vec3::y()).norm() < 1e-5);
//! assert!((manifold.max_depth() - 0.01).abs() < 1e-5);
//! // Lifted 10 cm clear of A, B has no contact within a 2 cm margin.
//! let apart = Pose::translation(0.0, 1.1, 0.0);
//! assert!(collide_cuboids(&cube, &a, &cube, &apart, 0.02).is_none());
//! ```
#![warn(missing_docs)]

mod axis_choice;
mod box_pair;
mod collide;
mod edge_contact;
mod face_contact;
pub mod feature_id;
mod margin;
mod sat;
pub mod tolerance;
mod vertex_contact;

#[cfg(test)]
mod tests;

pub use axis_choice::{AxisChoice, deepest_axis, preference_slack, preferred_axis};
pub use box_pair::BoxPair;
pub use collide::{
    ContactPolygon, EDGE_PAIR_COUNT, SUPPORTED_ASPECT, SUPPORTED_LENGTH, VERTEX_OF_A_FEATURE,
    collide_cuboids, collide_cuboids_cached, contact_polygon,
};
pub use edge_contact::{EdgeContact, edge_contact, support_edge};
pub use face_contact::{FaceContact, face_contact};
pub use margin::{BoxMotion, pair_margin};
pub use sat::{
    SatAxis, SatQuery, axis_separation, edge_axis, face_a_separation, face_b_separation,
};
pub use vertex_contact::{VertexContact, closest_vertex};

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
