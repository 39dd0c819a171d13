// requires: common/box_pair.wgsl
// The separating axis test over the 15 axes of two boxes and the choice of the contact axis
// (port of tumble-narrow's sat.rs and axis_choice.rs). The separation along a unit axis n
// from A to B is offset . n - r_A(n) - r_B(n), with r(n) = sum_k h_k |n . axis_k|.

// Stands in for the CPU's infinities (an unusable axis, a missing witness): WGSL has no
// infinite literal, and the largest finite float compares the same way with finite values.
const FLOAT_MAX: f32 = 3.40282347e38;

// Axis kinds, in the CPU's SatAxis order.
const AXIS_FACE_A: u32 = 0u;
const AXIS_FACE_B: u32 = 1u;
const AXIS_EDGE: u32 = 2u;

struct SatQuery {
    // Along A's axis i, oriented towards B.
    face_a: vec3<f32>,
    // Along B's axis j, oriented towards A.
    face_b: vec3<f32>,
    // Along a_i x b_j (index 3i + j), oriented from A to B; -FLOAT_MAX when skipped.
    edge: array<f32, 9>,
}

// One of the 15 axes and its separation.
struct AxisChoice {
    kind: u32,
    // Face 0..6 or edge axis 3i + j.
    index: u32,
    separation: f32,
}

fn face_a_separation(p: BoxPair, face: u32) -> f32 {
    let i = face / 2u;
    let sign = select(-1.0, 1.0, face % 2u == 0u);
    let radius_b = dot(mat_row(p.abs_rot, i), p.hb);
    return sign * p.offset[i] - p.ha[i] - radius_b;
}

fn face_b_separation(p: BoxPair, face: u32) -> f32 {
    let j = face / 2u;
    let sign = select(-1.0, 1.0, face % 2u == 0u);
    let radius_a = dot(p.abs_rot[j], p.ha);
    return -sign * dot(p.rot[j], p.offset) - p.hb[j] - radius_a;
}

fn face_a_facing(p: BoxPair, i: u32) -> u32 {
    return 2u * i + u32(p.offset[i] < 0.0);
}

fn face_b_facing(p: BoxPair, j: u32) -> u32 {
    return 2u * j + u32(dot(p.rot[j], p.offset) > 0.0);
}

// The unit edge axis a_i x b_j (A's frame, from A to B) in xyz, w = 1; w = 0 when the edges
// are within 1 mrad of parallel.
fn edge_axis(p: BoxPair, i: u32, j: u32) -> vec4<f32> {
    let axis = cross(unit_axis(i), p.rot[j]);
    let len_sq = dot(axis, axis);
    if len_sq < PARALLEL_EDGE_SIN_SQ {
        return vec4<f32>(0.0);
    }
    let n = axis / sqrt(len_sq);
    if dot(n, p.offset) < 0.0 {
        return vec4<f32>(-n, 1.0);
    }
    return vec4<f32>(n, 1.0);
}

fn axis_separation(p: BoxPair, n: vec3<f32>) -> f32 {
    let radius_a = dot(abs(n), p.ha);
    let radius_b = dot(abs(transpose(p.rot) * n), p.hb);
    return dot(n, p.offset) - radius_a - radius_b;
}

fn sat_query(p: BoxPair) -> SatQuery {
    var q: SatQuery;
    for (var i = 0u; i < 3u; i++) {
        q.face_a[i] = face_a_separation(p, face_a_facing(p, i));
        q.face_b[i] = face_b_separation(p, face_b_facing(p, i));
    }
    for (var k = 0u; k < 9u; k++) {
        let n = edge_axis(p, k / 3u, k % 3u);
        if n.w > 0.0 {
            q.edge[k] = axis_separation(p, n.xyz);
        } else {
            q.edge[k] = -FLOAT_MAX;
        }
    }
    return q;
}

// Index of the first largest of three.
fn argmax3(v: vec3<f32>) -> u32 {
    var best = 0u;
    if v.y > v[best] {
        best = 1u;
    }
    if v.z > v[best] {
        best = 2u;
    }
    return best;
}

fn best_face_a(p: BoxPair, q: SatQuery) -> AxisChoice {
    let i = argmax3(q.face_a);
    return AxisChoice(AXIS_FACE_A, face_a_facing(p, i), q.face_a[i]);
}

fn best_face_b(p: BoxPair, q: SatQuery) -> AxisChoice {
    let j = argmax3(q.face_b);
    return AxisChoice(AXIS_FACE_B, face_b_facing(p, j), q.face_b[j]);
}

fn best_edge(q: SatQuery) -> AxisChoice {
    var edges = q.edge;
    var best = 0u;
    for (var k = 1u; k < 9u; k++) {
        if edges[k] > edges[best] {
            best = k;
        }
    }
    return AxisChoice(AXIS_EDGE, best, edges[best]);
}

fn max_separation(q: SatQuery) -> f32 {
    var edges = q.edge;
    var m = max3(max(q.face_a, q.face_b));
    for (var k = 0u; k < 9u; k++) {
        m = max(m, edges[k]);
    }
    return m;
}

fn tolerance(separation: f32, rel: f32, abs_tol: f32, scale: f32) -> f32 {
    return rel * abs(separation) + abs_tol * scale;
}

// The axis of largest separation (ties: A's faces, then B's, then edges).
fn deepest_axis(p: BoxPair, q: SatQuery) -> AxisChoice {
    var choice = best_face_a(p, q);
    let fb = best_face_b(p, q);
    if fb.separation > choice.separation {
        choice = fb;
    }
    let e = best_edge(q);
    if e.separation > choice.separation {
        choice = e;
    }
    return choice;
}

// True when edge axis `edge` is within FACE_LIKE_EDGE_COS of the normal of `face` (a face
// axis choice) and the contact is shallow: a face contact seen through a slight tilt.
fn is_face_like(p: BoxPair, q: SatQuery, edge: u32, face: AxisChoice) -> bool {
    var face_separation = 0.0;
    var face_normal = vec3<f32>(0.0);
    if face.kind == AXIS_FACE_A {
        face_separation = face_a_separation(p, face.index);
        face_normal = unit_axis(face.index / 2u);
    } else if face.kind == AXIS_FACE_B {
        face_separation = face_b_separation(p, face.index);
        face_normal = p.rot[face.index / 2u];
    } else {
        return false;
    }
    if min(max_separation(q), face_separation) < -FACE_LIKE_MAX_DEPTH * feature_scale(p) {
        return false;
    }
    let n = edge_axis(p, edge / 3u, edge % 3u);
    return n.w > 0.0 && abs(dot(n.xyz, face_normal)) >= FACE_LIKE_EDGE_COS;
}

// The axis to build the contact on: B's face only when it beats A's by the face tolerance,
// an edge only when it beats both faces by the edge tolerance (the hysteresis tolerance for
// an edge axis within 3 degrees of the face normal), and last step's reference face
// (previous_kind, previous_feature; kind NO_PREVIOUS for none) while its separation stays
// within the hysteresis tolerance of the best.
fn preferred_axis(p: BoxPair, q: SatQuery, previous_kind: u32, previous_feature: u32) -> AxisChoice {
    let noise = noise_scale(p);
    let fa = best_face_a(p, q);
    let fb = best_face_b(p, q);
    let e = best_edge(q);
    var choice = fa;
    if fb.separation > fa.separation + tolerance(fa.separation, FACE_B_REL_TOL, FACE_B_ABS_TOL, noise) {
        choice = fb;
    }
    let best_face = max(fa.separation, fb.separation);
    var edge_slack = tolerance(best_face, EDGE_REL_TOL, EDGE_ABS_TOL, noise);
    if is_face_like(p, q, e.index, choice) {
        edge_slack = tolerance(best_face, HYSTERESIS_REL_TOL, HYSTERESIS_ABS_TOL, feature_scale(p));
    }
    if e.separation > best_face + edge_slack {
        choice = e;
    }
    var kept = AxisChoice(AXIS_EDGE, 0u, 0.0);
    var has_kept = false;
    if previous_kind == MANIFOLD_FACE_A && previous_feature < 6u {
        kept = AxisChoice(AXIS_FACE_A, previous_feature, face_a_separation(p, previous_feature));
        has_kept = true;
    } else if previous_kind == MANIFOLD_FACE_B && previous_feature < 6u {
        kept = AxisChoice(AXIS_FACE_B, previous_feature, face_b_separation(p, previous_feature));
        has_kept = true;
    }
    if has_kept {
        let best = max_separation(q);
        let slack = tolerance(best, HYSTERESIS_REL_TOL, HYSTERESIS_ABS_TOL, feature_scale(p));
        if kept.separation >= best - slack {
            choice = kept;
        }
    }
    return choice;
}
