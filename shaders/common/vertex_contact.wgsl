// requires: common/box_pair.wgsl
// The closest vertex pair of two separated boxes (port of tumble-narrow's
// vertex_contact.rs): every vertex of each box against the other box, 16 clamps.

struct VertexContact {
    point_a: vec3<f32>,
    point_b: vec3<f32>,
    // From point_a to point_b, computed where both are known at the gap's scale: the normal's
    // direction (point_b - point_a loses its low digits beside a much larger vertex).
    gap: vec3<f32>,
    distance: f32,
    vertex: u32,
    on_a: bool,
}

fn closest_vertex(p: BoxPair) -> VertexContact {
    var best = VertexContact(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), FLOAT_MAX, 0u, false);
    for (var v = 0u; v < 8u; v++) {
        // B's vertex against A, in A's frame.
        let vb = b_to_a(p, box_vertex(p.hb, v));
        let on_a = box_closest_point(p.ha, vb);
        let gap_b = vb - on_a;
        let db = length(gap_b);
        if db < best.distance {
            best = VertexContact(on_a, vb, gap_b, db, v, false);
        }
        // A's vertex against B, in B's frame; the gap vector is rotated back to A's frame
        // rather than the point, so it keeps the digits of a gap much shorter than the boxes.
        let va = box_vertex(p.ha, v);
        let va_in_b = a_to_b(p, va);
        let gap = p.rot * (box_closest_point(p.hb, va_in_b) - va_in_b);
        let da = length(gap);
        if da < best.distance {
            best = VertexContact(va, va + gap, gap, da, v, true);
        }
    }
    return best;
}

fn vertex_point_id(vertex: u32, on_a: bool) -> u32 {
    return (ID_KIND_VERTEX << ID_KIND_SHIFT) | (u32(on_a) << ID_FIELD_SHIFT) | vertex;
}
