// requires: common/contact_polygon.wgsl
// Edge-edge contacts (port of tumble-narrow's edge_contact.rs and tumble-geometry's segment
// closest points): one point midway between the closest points of the two support edges.

struct SegmentClosest {
    point_a: vec3<f32>,
    point_b: vec3<f32>,
}

// For parallel segments: the middle of the overlap of [s0, s1] with [0, 1], or the nearer end.
fn parallel_overlap_middle(s0: f32, s1: f32) -> f32 {
    let lo = max(min(s0, s1), 0.0);
    let hi = min(max(s0, s1), 1.0);
    if lo <= hi {
        return 0.5 * (lo + hi);
    }
    if max(s0, s1) < 0.0 {
        return 0.0;
    }
    return 1.0;
}

// Closest points of segments a0 -> a1 and b0 -> b1, robust for parallel and zero-length ones.
fn closest_points_segments(a0: vec3<f32>, a1: vec3<f32>, b0: vec3<f32>, b1: vec3<f32>) -> SegmentClosest {
    let d1 = a1 - a0;
    let d2 = b1 - b0;
    let r = a0 - b0;
    let a = dot(d1, d1);
    let e = dot(d2, d2);
    let f = dot(d2, r);
    let a_is_point = a <= SEGMENT_DEGENERATE_RATIO * (a + e);
    let b_is_point = e <= SEGMENT_DEGENERATE_RATIO * (a + e);
    var s = 0.0;
    var t = 0.0;
    if a_is_point && b_is_point {
        s = 0.0;
        t = 0.0;
    } else if a_is_point {
        t = clamp(f / e, 0.0, 1.0);
    } else if b_is_point {
        s = clamp(-dot(d1, r) / a, 0.0, 1.0);
    } else {
        let b = dot(d1, d2);
        let c = dot(d1, r);
        let cr = cross(d1, d2);
        let denom = dot(cr, cr);
        var s_line = 0.0;
        if denom > SEGMENT_PARALLEL_SIN_SQ * a * e {
            s_line = clamp((b * f - c * e) / denom, 0.0, 1.0);
        } else {
            s_line = parallel_overlap_middle(-c / a, (b - c) / a);
        }
        // The best t for this s, then the best s for a clamped t.
        let t_line = (b * s_line + f) / e;
        if t_line < 0.0 {
            s = clamp(-c / a, 0.0, 1.0);
            t = 0.0;
        } else if t_line > 1.0 {
            s = clamp((b - c) / a, 0.0, 1.0);
            t = 1.0;
        } else {
            s = s_line;
            t = t_line;
        }
    }
    return SegmentClosest(a0 + d1 * s, b0 + d2 * t);
}

// The edge along `axis` farthest along local direction dir (CUBOID_EDGES numbering).
fn support_edge(axis: u32, dir: vec3<f32>) -> u32 {
    let lo = min((axis + 1u) % 3u, (axis + 2u) % 3u);
    let hi = max((axis + 1u) % 3u, (axis + 2u) % 3u);
    return 4u * axis + u32(dir[lo] >= 0.0) + 2u * u32(dir[hi] >= 0.0);
}

struct EdgeContact {
    edge_a: u32,
    edge_b: u32,
    closest: SegmentClosest,
    // Overlap along the axis: positive when the edges pass through each other.
    depth: f32,
}

// A's support edge along `normal` (A's frame, from A to B) on axis i, B's along -normal on
// axis j, and their closest points.
fn edge_contact(p: BoxPair, i: u32, j: u32, normal: vec3<f32>) -> EdgeContact {
    let edge_a = support_edge(i, normal);
    let edge_b = support_edge(j, -(transpose(p.rot) * normal));
    let va = edge_vertices(edge_a);
    let vb = edge_vertices(edge_b);
    let closest = closest_points_segments(
        box_vertex(p.ha, va.x),
        box_vertex(p.ha, va.y),
        b_to_a(p, box_vertex(p.hb, vb.x)),
        b_to_a(p, box_vertex(p.hb, vb.y)),
    );
    return EdgeContact(edge_a, edge_b, closest, dot(closest.point_a - closest.point_b, normal));
}

fn edge_point_id(edge_a: u32, edge_b: u32) -> u32 {
    return (ID_KIND_EDGE << ID_KIND_SHIFT) | (edge_a << ID_FIELD_SHIFT) | edge_b;
}
