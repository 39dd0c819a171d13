// requires: common/contact_polygon.wgsl
// Face contacts (port of tumble-narrow's face_contact.rs): the incident face of box B clipped
// against the four side planes of A's reference face, all in A's frame, keeping the points
// deeper than -margin. Pass a swapped pair for a reference face on B.

fn face_point_id(kind: u32, reference: u32, incident: u32, edge_in: u32, edge_out: u32) -> u32 {
    return (kind << ID_KIND_SHIFT) | (reference << ID_REFERENCE_SHIFT)
        | (incident << ID_INCIDENT_SHIFT) | (edge_in << ID_FIELD_SHIFT) | edge_out;
}

// Fills `out` with the points (positions in the reference box's frame) and returns the
// smallest separation over the whole clipped polygon (FLOAT_MAX when it is empty).
fn face_contact(p: BoxPair, reference: u32, margin: f32, kind: u32, out: ptr<function, ContactPolygon>) -> f32 {
    let axis = reference / 2u;
    let sign = select(-1.0, 1.0, reference % 2u == 0u);
    let normal = unit_axis(axis) * sign;
    let height = p.ha[axis];

    // The incident face: the face of the other box most anti-parallel to the reference normal.
    let normal_in_b = transpose(p.rot) * normal;
    let incident = best_face(-normal_in_b);
    let corners = CUBOID_FACES[incident];
    var polygon: ClipPolygon;
    polygon.len = 0u;
    for (var k = 0u; k < 4u; k++) {
        let corner = b_to_a(p, box_vertex(p.hb, corners[k]));
        push_vertex(&polygon, ClipVertex(corner, (k + 3u) % 4u, k));
    }

    // The four side planes, two per axis across the normal: slot 0 for the lower axis.
    var slot = 0u;
    for (var side = 0u; side < 3u; side++) {
        if side == axis {
            continue;
        }
        let label = SIDE_LABEL_BASE + 2u * slot;
        clip_polygon(&polygon, unit_axis(side), p.ha[side], label);
        clip_polygon(&polygon, -unit_axis(side), p.ha[side], label + 1u);
        slot += 1u;
    }

    var min_separation = FLOAT_MAX;
    for (var k = 0u; k < polygon.len; k++) {
        let v = polygon.vertices[k];
        let depth = height - dot(normal, v.position);
        min_separation = min(min_separation, -depth);
        if depth >= -margin {
            let id = face_point_id(kind, reference, incident, v.edge_in, v.edge_out);
            // Midway between the incident point and its projection on the reference face.
            push_point(out, PolygonPoint(v.position + normal * (0.5 * depth), depth, id));
        }
    }
    return min_separation;
}
