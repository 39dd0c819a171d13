// requires: common/box_pair.wgsl
// Contact polygons: Sutherland-Hodgman clipping with feature labels (port of tumble-geometry's
// clip.rs) and the point list a contact is built in, before reduction to four points.

// A polygon vertex and the labels of the edges arriving at and leaving it.
struct ClipVertex {
    position: vec3<f32>,
    edge_in: u32,
    edge_out: u32,
}

struct ClipPolygon {
    vertices: array<ClipVertex, MAX_CLIP_VERTICES>,
    len: u32,
}

// A contact point before reduction, in world space.
struct PolygonPoint {
    position: vec3<f32>,
    depth: f32,
    id: u32,
}

// A contact on one axis: normal from A to B, kind (MANIFOLD_*), feature, points.
struct ContactPolygon {
    normal: vec3<f32>,
    kind: u32,
    feature: u32,
    points: array<PolygonPoint, MAX_CLIP_VERTICES>,
    len: u32,
}

fn empty_contact() -> ContactPolygon {
    var c: ContactPolygon;
    c.normal = vec3<f32>(0.0);
    c.kind = MANIFOLD_FACE_A;
    c.feature = 0u;
    c.len = 0u;
    return c;
}

fn push_point(c: ptr<function, ContactPolygon>, p: PolygonPoint) {
    if (*c).len < MAX_CLIP_VERTICES {
        (*c).points[(*c).len] = p;
        (*c).len += 1u;
    }
}

fn push_vertex(poly: ptr<function, ClipPolygon>, v: ClipVertex) {
    if (*poly).len < MAX_CLIP_VERTICES {
        (*poly).vertices[(*poly).len] = v;
        (*poly).len += 1u;
    }
}

// The part of poly on the non-positive side of the plane normal . x = offset; a vertex made
// where an edge labelled L leaves the kept side is (L, label), where it re-enters (label, L).
fn clip_polygon(poly: ptr<function, ClipPolygon>, normal: vec3<f32>, offset: f32, label: u32) {
    var out: ClipPolygon;
    out.len = 0u;
    let n = (*poly).len;
    if n == 0u {
        return;
    }
    var prev = (*poly).vertices[n - 1u];
    var prev_dist = dot(normal, prev.position) - offset;
    for (var k = 0u; k < n; k++) {
        let cur = (*poly).vertices[k];
        let cur_dist = dot(normal, cur.position) - offset;
        let prev_inside = prev_dist <= 0.0;
        let cur_inside = cur_dist <= 0.0;
        if prev_inside != cur_inside {
            // The signs differ, so the denominator is non-zero and t lies in [0, 1].
            let t = prev_dist / (prev_dist - cur_dist);
            let position = prev.position + (cur.position - prev.position) * t;
            if prev_inside {
                push_vertex(&out, ClipVertex(position, prev.edge_out, label));
            } else {
                push_vertex(&out, ClipVertex(position, label, prev.edge_out));
            }
        }
        if cur_inside {
            push_vertex(&out, cur);
        }
        prev = cur;
        prev_dist = cur_dist;
    }
    *poly = out;
}
