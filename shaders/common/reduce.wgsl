// requires: common/contact_polygon.wgsl
// Reduction of a contact polygon to at most four points (port of tumble-geometry's
// reduce.rs, the thesis's Algorithm 8): the deepest point, the point farthest from it, the
// point making the largest triangle with those, and the point adding the most area outside
// that triangle. Kept points keep their input order. Areas are measured across the normal.

fn twice_signed_area(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, normal: vec3<f32>) -> f32 {
    return dot(cross(b - a, c - a), normal);
}

// Rust's f32::signum for the finite values met here: the sign bit decides, so +0 gives +1.
fn signum(x: f32) -> f32 {
    return select(1.0, -1.0, (bitcast<u32>(x) & 0x80000000u) != 0u);
}

// Area the point q adds outside the triangle (p0, p1, p2) oriented by `orientation`.
fn added_area(q: vec3<f32>, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, normal: vec3<f32>, orientation: f32) -> f32 {
    let o01 = -orientation * twice_signed_area(p0, p1, q, normal);
    let o12 = -orientation * twice_signed_area(p1, p2, q, normal);
    let o20 = -orientation * twice_signed_area(p2, p0, q, normal);
    return max(max(o01, o12), o20);
}

// The chosen indices in ascending order (slots past the returned count are unused).
struct Selection {
    index: array<u32, MAX_MANIFOLD_POINTS>,
    len: u32,
}

fn select_push(s: ptr<function, Selection>, i: u32, area: f32) {
    if !(area > 0.0) {
        return;
    }
    for (var k = 0u; k < (*s).len; k++) {
        if (*s).index[k] == i {
            return;
        }
    }
    (*s).index[(*s).len] = i;
    (*s).len += 1u;
}

fn select_four(c: ptr<function, ContactPolygon>) -> Selection {
    var s: Selection;
    s.len = 0u;
    let n = (*c).len;
    if n <= MAX_MANIFOLD_POINTS {
        for (var i = 0u; i < n; i++) {
            s.index[i] = i;
        }
        s.len = n;
        return s;
    }
    let normal = (*c).normal;
    // Each argmax keeps the first best (strictly greater replaces), as on the CPU.
    var i0 = 0u;
    var best = -FLOAT_MAX;
    for (var i = 0u; i < n; i++) {
        let score = (*c).points[i].depth;
        if i == 0u || score > best {
            best = score;
            i0 = i;
        }
    }
    let p0 = (*c).points[i0].position;
    var i1 = 0u;
    best = -FLOAT_MAX;
    for (var i = 0u; i < n; i++) {
        let d = (*c).points[i].position - p0;
        let score = dot(d, d);
        if i == 0u || score > best {
            best = score;
            i1 = i;
        }
    }
    let p1 = (*c).points[i1].position;
    var i2 = 0u;
    best = -FLOAT_MAX;
    for (var i = 0u; i < n; i++) {
        let score = abs(twice_signed_area(p0, p1, (*c).points[i].position, normal));
        if i == 0u || score > best {
            best = score;
            i2 = i;
        }
    }
    let p2 = (*c).points[i2].position;
    let orientation = signum(twice_signed_area(p0, p1, p2, normal));
    var i3 = 0u;
    best = -FLOAT_MAX;
    for (var i = 0u; i < n; i++) {
        let score = added_area((*c).points[i].position, p0, p1, p2, normal, orientation);
        if i == 0u || score > best {
            best = score;
            i3 = i;
        }
    }
    let d01 = p1 - p0;
    select_push(&s, i0, 1.0);
    select_push(&s, i1, dot(d01, d01));
    select_push(&s, i2, abs(twice_signed_area(p0, p1, p2, normal)));
    select_push(&s, i3, added_area((*c).points[i3].position, p0, p1, p2, normal, orientation));
    // Ascending order (at most four entries: insertion sort).
    for (var k = 1u; k < s.len; k++) {
        let v = s.index[k];
        var m = k;
        while m > 0u && s.index[m - 1u] > v {
            s.index[m] = s.index[m - 1u];
            m -= 1u;
        }
        s.index[m] = v;
    }
    return s;
}
