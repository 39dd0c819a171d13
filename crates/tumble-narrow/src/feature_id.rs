//! Contact point ids: which features of the two boxes make a point, packed into a `u32`.
//!
//! An id only has to be the same from one step to the next while the same features touch, and
//! different from the other points of its manifold; the solver matches last step's points by it
//! to carry their impulses over.
//!
//! Bits, from the least significant:
//!
//! | bits  | face contact (kind 0: A's face is reference, 1: B's) | edge contact (kind 2) | vertex contact (kind 3) |
//! |-------|--------------------------------------------------|-----------------------|-------------------------|
//! | 0-3   | `edge_out` label of the clipped vertex            | edge of B (0..12)     | vertex (0..8)           |
//! | 4-7   | `edge_in` label of the clipped vertex             | edge of A (0..12)     | 0: B's vertex, 1: A's   |
//! | 8-10  | incident face (0..6)                              | 0                     | 0                       |
//! | 11-13 | reference face (0..6)                             | 0                     | 0                       |
//! | 14-15 | kind                                              | kind                  | kind                    |
//!
//! Clip labels (see `tumble_geometry::ClipVertex`): `0..4` are the incident face's edges (edge `k`
//! from corner `k` to corner `k + 1` of `CUBOID_FACES[incident]`), `4..8` the reference face's
//! side planes ([`SIDE_LABEL_BASE`] + `2 * slot + negative`, slot 0 for the lower of the two axes
//! across the reference normal). So an incident corner is `(k - 1, k)`, an incident edge cut by a
//! side is `(k, side)` or `(side, k)`, and a reference corner inside the incident face is
//! `(side, side')`.

/// Kind code of a face contact whose reference face is on A.
pub const KIND_FACE_A: u32 = 0;
/// Kind code of a face contact whose reference face is on B.
pub const KIND_FACE_B: u32 = 1;
/// Kind code of an edge-edge contact.
pub const KIND_EDGE: u32 = 2;
/// Kind code of a vertex contact (boxes apart, closest pair at a vertex).
pub const KIND_VERTEX: u32 = 3;

/// First clip label of the reference side planes (labels below it are incident face edges).
pub const SIDE_LABEL_BASE: u32 = 4;

const KIND_SHIFT: u32 = 14;
const REFERENCE_SHIFT: u32 = 11;
const INCIDENT_SHIFT: u32 = 8;
const FIELD_SHIFT: u32 = 4;

/// Id of a clipped face contact point.
pub fn face_point_id(kind: u32, reference: u32, incident: u32, edge_in: u32, edge_out: u32) -> u32 {
    (kind << KIND_SHIFT)
        | (reference << REFERENCE_SHIFT)
        | (incident << INCIDENT_SHIFT)
        | (edge_in << FIELD_SHIFT)
        | edge_out
}

/// Id of an edge-edge contact point.
pub fn edge_point_id(edge_a: u32, edge_b: u32) -> u32 {
    (KIND_EDGE << KIND_SHIFT) | (edge_a << FIELD_SHIFT) | edge_b
}

/// Id of a vertex contact point: `vertex` of A when `on_a`, else of B.
pub fn vertex_point_id(vertex: u32, on_a: bool) -> u32 {
    (KIND_VERTEX << KIND_SHIFT) | (u32::from(on_a) << FIELD_SHIFT) | vertex
}

/// The kind code stored in an id.
pub fn id_kind(id: u32) -> u32 {
    id >> KIND_SHIFT
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_face_contact_field_combination_gets_its_own_id() {
        let mut ids = std::collections::HashSet::new();
        for kind in [KIND_FACE_A, KIND_FACE_B] {
            for reference in 0..6 {
                for incident in 0..6 {
                    for edge_in in 0..8 {
                        for edge_out in 0..8 {
                            let id = face_point_id(kind, reference, incident, edge_in, edge_out);
                            assert_eq!(id_kind(id), kind);
                            assert!(ids.insert(id));
                        }
                    }
                }
            }
        }
        for a in 0..12 {
            for b in 0..12 {
                assert!(ids.insert(edge_point_id(a, b)));
            }
        }
        for v in 0..8 {
            assert!(ids.insert(vertex_point_id(v, true)));
            assert!(ids.insert(vertex_point_id(v, false)));
        }
    }
}
