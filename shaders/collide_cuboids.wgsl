// collide_cuboids: one thread per candidate pair builds the pair's contact manifold (port of
// tumble-narrow's collide.rs): SAT over 15 axes, the preferred axis with last step's
// reference face as hysteresis, a face contact (clipping) or an edge contact on it, the
// closest-pair check when the boxes are apart, and the reduction to four points. A pair
// without contact gets len = 0. Manifold k belongs to pair k.

@group(0) @binding(0) var<uniform> params: NarrowParams;
@group(0) @binding(1) var<storage, read> work: WorkList;
@group(0) @binding(2) var<storage, read> pair_a: array<u32>;
@group(0) @binding(3) var<storage, read> pair_b: array<u32>;
@group(0) @binding(4) var<storage, read> poses: array<GpuPose>;
@group(0) @binding(5) var<storage, read> velocities: array<GpuVelocity>;
@group(0) @binding(6) var<storage, read> shapes: array<GpuShape>;
@group(0) @binding(7) var<storage, read> previous_index: array<u32>;
@group(0) @binding(8) var<storage, read> previous_manifolds: array<GpuManifold>;
@group(0) @binding(9) var<storage, read_write> manifolds: array<GpuManifold>;
@group(0) @binding(10) var<storage, read_write> contacts: array<GpuContact>;

fn half_extents(i: u32) -> vec3<f32> {
    let s = shapes[i];
    return vec3<f32>(s.hx, s.hy, s.hz);
}

fn transform_point(pose: GpuPose, v: vec3<f32>) -> vec3<f32> {
    return quat_rotate(pose.rotation, v) + pose.position.xyz;
}

// The pair's speculative margin: the base margin plus how far the boxes can close in one
// step (relative speed plus each spin's rim speed, times dt), as the CPU world computes it.
fn pair_margin(a: u32, b: u32) -> f32 {
    let va = velocities[a];
    let vb = velocities[b];
    let closing = length(vb.linear.xyz - va.linear.xyz)
        + length(va.angular.xyz) * length(half_extents(a))
        + length(vb.angular.xyz) * length(half_extents(b));
    return params.margin + closing * params.dt;
}

// The contact on one axis, in world space, into `out`; returns how far apart its closest
// pair is (FLOAT_MAX when it has none).
fn build(p: BoxPair, pose_a: GpuPose, pose_b: GpuPose, axis: AxisChoice, margin: f32, out: ptr<function, ContactPolygon>) -> f32 {
    *out = empty_contact();
    var witness = FLOAT_MAX;
    if axis.kind == AXIS_FACE_A {
        witness = face_contact(p, axis.index, margin, ID_KIND_FACE_A, out);
        let sign = select(-1.0, 1.0, axis.index % 2u == 0u);
        (*out).normal = quat_rotate(pose_a.rotation, unit_axis(axis.index / 2u) * sign);
        (*out).kind = MANIFOLD_FACE_A;
        (*out).feature = axis.index;
        for (var k = 0u; k < (*out).len; k++) {
            (*out).points[k].position = transform_point(pose_a, (*out).points[k].position);
        }
    } else if axis.kind == AXIS_FACE_B {
        // The same construction seen from B; the normal points from A to B, against B's
        // outward face normal.
        witness = face_contact(swapped(p), axis.index, margin, ID_KIND_FACE_B, out);
        let sign = select(-1.0, 1.0, axis.index % 2u == 0u);
        (*out).normal = -quat_rotate(pose_b.rotation, unit_axis(axis.index / 2u) * sign);
        (*out).kind = MANIFOLD_FACE_B;
        (*out).feature = axis.index;
        for (var k = 0u; k < (*out).len; k++) {
            (*out).points[k].position = transform_point(pose_b, (*out).points[k].position);
        }
    } else {
        let n = edge_axis(p, axis.index / 3u, axis.index % 3u);
        if n.w > 0.0 {
            let c = edge_contact(p, axis.index / 3u, axis.index % 3u, n.xyz);
            (*out).normal = quat_rotate(pose_a.rotation, n.xyz);
            (*out).kind = MANIFOLD_EDGE;
            (*out).feature = c.edge_a * 12u + c.edge_b;
            if c.depth >= -margin {
                let mid = 0.5 * (c.closest.point_a + c.closest.point_b);
                push_point(out, PolygonPoint(transform_point(pose_a, mid), c.depth, edge_point_id(c.edge_a, c.edge_b)));
            }
            // Apart, the closest pair's length is a true distance; overlapping, the depth.
            if c.depth < 0.0 {
                witness = length(c.closest.point_b - c.closest.point_a);
            } else {
                witness = -c.depth;
            }
        }
    }
    return witness;
}

// The closest vertex pair as a one-point contact along its own direction; none when the
// pair is too close for that direction to be defined.
fn vertex_candidate(p: BoxPair, pose_a: GpuPose, min_distance: f32, out: ptr<function, ContactPolygon>) -> f32 {
    *out = empty_contact();
    let v = closest_vertex(p);
    if !(v.distance > min_distance) {
        return FLOAT_MAX;
    }
    (*out).normal = quat_rotate(pose_a.rotation, (v.point_b - v.point_a) / v.distance);
    (*out).kind = MANIFOLD_EDGE;
    (*out).feature = select(EDGE_PAIR_COUNT, VERTEX_OF_A_FEATURE, v.on_a) + v.vertex;
    let mid = 0.5 * (v.point_a + v.point_b);
    push_point(out, PolygonPoint(transform_point(pose_a, mid), -v.distance, vertex_point_id(v.vertex, v.on_a)));
    return v.distance;
}

// Candidate c of the apart case: 0 the preferred axis, 1 the deepest, 2 the best edge,
// 3 the closest vertex pair.
fn build_candidate(c: u32, p: BoxPair, pose_a: GpuPose, pose_b: GpuPose, chosen: AxisChoice, deepest: AxisChoice, edge: AxisChoice, margin: f32, slack: f32, out: ptr<function, ContactPolygon>) -> f32 {
    switch c {
        case 0u: {
            return build(p, pose_a, pose_b, chosen, margin, out);
        }
        case 1u: {
            return build(p, pose_a, pose_b, deepest, margin, out);
        }
        case 2u: {
            return build(p, pose_a, pose_b, edge, margin, out);
        }
        default: {
            return vertex_candidate(p, pose_a, slack, out);
        }
    }
}

// The contact polygon of pair k (len 0: no contact).
fn contact_for_pair(k: u32, a: u32, b: u32, out: ptr<function, ContactPolygon>) {
    *out = empty_contact();
    let pose_a = poses[a];
    let pose_b = poses[b];
    let p = make_box_pair(half_extents(a), pose_a, half_extents(b), pose_b);
    let q = sat_query(p);
    let best = max_separation(q);
    let margin = pair_margin(a, b);
    // The SAT separation never exceeds the distance: past the margin nothing can touch.
    if !(best <= margin) {
        return;
    }
    var previous_kind = NO_PREVIOUS;
    var previous_feature = 0u;
    let prev = previous_index[k];
    if prev != NO_PREVIOUS && previous_manifolds[prev].len > 0u {
        previous_kind = previous_manifolds[prev].kind;
        previous_feature = previous_manifolds[prev].feature;
    }
    let chosen = preferred_axis(p, q, previous_kind, previous_feature);
    let deepest = deepest_axis(p, q);
    let first_witness = build(p, pose_a, pose_b, chosen, margin, out);

    if best <= 0.0 {
        // Overlap: the deepest axis always has points; a preferred one almost always does.
        if (*out).len == 0u {
            build(p, pose_a, pose_b, deepest, margin, out);
        }
        return;
    }
    // Apart: the contact is right when its closest pair is as far apart as the separation.
    let slack = WITNESS_TOL * noise_scale(p);
    if first_witness <= best + slack {
        return;
    }
    // Otherwise the closest pair is elsewhere: measure every candidate, keep the first whose
    // witness is (within slack) the distance, and rebuild it.
    let edge = best_edge(q);
    var witness = array<f32, 4>(first_witness, 0.0, 0.0, 0.0);
    var count = array<u32, 4>((*out).len, 0u, 0u, 0u);
    var scratch: ContactPolygon;
    for (var c = 1u; c < 4u; c++) {
        witness[c] = build_candidate(c, p, pose_a, pose_b, chosen, deepest, edge, margin, slack, &scratch);
        count[c] = scratch.len;
    }
    let distance = min(min(witness[0], witness[1]), min(witness[2], witness[3]));
    var pick = 4u;
    if distance <= margin {
        for (var c = 0u; c < 4u; c++) {
            if witness[c] <= distance + slack && count[c] > 0u {
                pick = c;
                break;
            }
        }
    }
    if pick == 4u {
        *out = empty_contact();
    } else if pick != 0u {
        build_candidate(pick, p, pose_a, pose_b, chosen, deepest, edge, margin, slack, out);
    }
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let k = linear_index(workgroup, groups, local);
    if k >= work.count {
        return;
    }
    let a = pair_a[k];
    let b = pair_b[k];
    var polygon: ContactPolygon;
    contact_for_pair(k, a, b, &polygon);
    var manifold: GpuManifold;
    manifold.normal = vec4<f32>(polygon.normal, 0.0);
    manifold.body_a = a;
    manifold.body_b = b;
    manifold.kind = polygon.kind;
    manifold.feature = polygon.feature;
    manifold.previous = previous_index[k];
    let chosen = select_four(&polygon);
    manifold.len = chosen.len;
    for (var s = 0u; s < MAX_MANIFOLD_POINTS; s++) {
        var contact: GpuContact;
        if s < chosen.len {
            let point = polygon.points[chosen.index[s]];
            contact.position = vec4<f32>(point.position, 0.0);
            contact.depth = point.depth;
            contact.id = point.id;
        }
        contacts[k * MAX_MANIFOLD_POINTS + s] = contact;
    }
    manifolds[k] = manifold;
}
