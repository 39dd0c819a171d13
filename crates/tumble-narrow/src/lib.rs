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
    ContactPolygon, EDGE_PAIR_COUNT, SUPPORTED_LENGTH, VERTEX_OF_A_FEATURE, collide_cuboids,
    collide_cuboids_cached, contact_polygon,
};
pub use edge_contact::{EdgeContact, edge_contact, support_edge};
pub use face_contact::{FaceContact, face_contact};
pub use margin::{BoxMotion, pair_margin};
pub use sat::{
    SatAxis, SatQuery, axis_separation, edge_axis, face_a_separation, face_b_separation,
};
pub use vertex_contact::{VertexContact, closest_vertex};
