// requires: common/indexing.wgsl common/sat.wgsl common/face_contact.wgsl common/edge_contact.wgsl common/vertex_contact.wgsl common/reduce.wgsl common/recycle.wgsl
// collide_cuboids: one thread per candidate pair builds the pair's contact manifold (port of
// tumble-narrow's collide.rs): SAT over 15 axes, the preferred axis with last step's
// reference face as hysteresis, a face contact (clipping) or an edge contact on it, the
// closest-pair check when the boxes are apart, and the reduction to four points. A pair
// without contact gets len = 0. Manifold k belongs to pair k. With params.recycle_distance
// above 0, a pair whose bodies barely moved relative to each other since its manifold was
// last computed keeps it instead (common/recycle.wgsl), with the same ids, kind and feature,
// and is marked `recycled`. The pairs of a workgroup that need the full test are then listed
// (a workgroup atomic) and run by the workgroup's first threads, so that they fill whole warps: a
// warp runs as long as its slowest thread, and with most pairs recycled a warp would otherwise
// hold one or two full tests among recycled threads that wait for them. Each result is still
// written at its own pair's index, so the output does not depend on the order.

@group(0) @binding(0) var<uniform> params: NarrowParams;
// This step's pair `WorkList`.
@group(0) @binding(1) var<storage, read> work: WorkList;
// Sorted pairs, first bodies.
@group(0) @binding(2) var<storage, read> pair_a: array<u32>;
// Sorted pairs, second bodies.
@group(0) @binding(3) var<storage, read> pair_b: array<u32>;
@group(0) @binding(4) var<storage, read> poses: array<GpuPose>;
// `array<GpuVelocity>` (for the speculative margin).
@group(0) @binding(5) var<storage, read> velocities: array<GpuVelocity>;
@group(0) @binding(6) var<storage, read> shapes: array<GpuShape>;
// From `match_pairs`.
@group(0) @binding(7) var<storage, read> previous_index: array<u32>;
// Last step's manifolds (for the reference-face hysteresis).
@group(0) @binding(8) var<storage, read> previous_manifolds: array<GpuManifold>;
// Output manifolds, one per pair.
@group(0) @binding(9) var<storage, read_write> manifolds: array<GpuManifold>;
// Output points, `MAX_MANIFOLD_POINTS` per pair.
@group(0) @binding(10) var<storage, read_write> contacts: array<GpuContact>;
// Last step's points (their feature ids, for a recycled manifold).
@group(0) @binding(11) var<storage, read> previous_contacts: array<GpuContact>;
// Last step's manifolds in their body A's frame (the anchors of recycling).
@group(0) @binding(12) var<storage, read> previous_locals: array<GpuLocalManifold>;

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

// How good a contact built on one axis is: its separation along that axis, and how far
// apart its closest pair of surface points is (FLOAT_MAX when it has none).
struct Candidate {
    separation: f32,
    witness: f32,
}

// The contact on one axis, in world space, into `out`.
fn build(p: BoxPair, pose_a: GpuPose, pose_b: GpuPose, axis: AxisChoice, margin: f32, out: ptr<function, ContactPolygon>) -> Candidate {
    *out = empty_contact();
    var c = Candidate(-FLOAT_MAX, FLOAT_MAX);
    if axis.kind == AXIS_FACE_A {
        c.witness = face_contact(p, axis.index, margin, ID_KIND_FACE_A, out);
        c.separation = face_a_separation(p, axis.index);
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
        c.witness = face_contact(swapped(p), axis.index, margin, ID_KIND_FACE_B, out);
        c.separation = face_b_separation(p, axis.index);
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
            let e = edge_contact(p, axis.index / 3u, axis.index % 3u, n.xyz);
            (*out).normal = quat_rotate(pose_a.rotation, n.xyz);
            (*out).kind = MANIFOLD_EDGE;
            (*out).feature = e.edge_a * 12u + e.edge_b;
            if e.depth >= -margin {
                let mid = 0.5 * (e.closest.point_a + e.closest.point_b);
                push_point(out, PolygonPoint(transform_point(pose_a, mid), e.depth, edge_point_id(e.edge_a, e.edge_b)));
            }
            // The closest pair of two surface segments: a true distance between the surfaces
            // (used only when the boxes are apart, where it bounds their distance).
            c.witness = length(e.closest.point_b - e.closest.point_a);
            c.separation = axis_separation(p, n.xyz);
        }
    }
    return c;
}

// The closest vertex pair as a one-point contact along its own direction; none when the
// pair is too close for that direction to be defined.
fn vertex_candidate(p: BoxPair, pose_a: GpuPose, min_distance: f32, out: ptr<function, ContactPolygon>) -> Candidate {
    *out = empty_contact();
    let v = closest_vertex(p);
    if !(v.distance > min_distance) {
        return Candidate(-FLOAT_MAX, FLOAT_MAX);
    }
    (*out).normal = quat_rotate(pose_a.rotation, v.gap / v.distance);
    (*out).kind = MANIFOLD_EDGE;
    (*out).feature = select(EDGE_PAIR_COUNT, VERTEX_OF_A_FEATURE, v.on_a) + v.vertex;
    let mid = 0.5 * (v.point_a + v.point_b);
    push_point(out, PolygonPoint(transform_point(pose_a, mid), -v.distance, vertex_point_id(v.vertex, v.on_a)));
    return Candidate(v.distance, v.distance);
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
    let first = build(p, pose_a, pose_b, chosen, margin, out);

    if best <= 0.0 {
        // Overlap: the deepest axis always has points; a preferred one almost always does.
        if (*out).len == 0u {
            build(p, pose_a, pose_b, deepest, margin, out);
        }
        return;
    }
    // Apart: a contact built on an SAT axis is right when its closest pair is no farther
    // apart than the separation along that axis (then both are the distance). Try the
    // preferred, the deepest and the best edge axis; otherwise the closest pair has a vertex
    // on one side and its own direction is the normal.
    let slack = WITNESS_TOL * noise_scale(p);
    if first.witness <= first.separation + slack && (*out).len > 0u {
        return;
    }
    let second = build(p, pose_a, pose_b, deepest, margin, out);
    if second.witness <= second.separation + slack && (*out).len > 0u {
        return;
    }
    let third = build(p, pose_a, pose_b, best_edge(q), margin, out);
    if third.witness <= third.separation + slack && (*out).len > 0u {
        return;
    }
    let vertex = vertex_candidate(p, pose_a, slack, out);
    if !(vertex.witness <= margin) {
        *out = empty_contact();
    }
}

// Pair k's manifold reused from last step when the pair may recycle it (written with its
// points, and true); false when the pair needs a fresh one.
fn try_recycle(k: u32, a: u32, b: u32) -> bool {
    let prev = previous_index[k];
    if !(params.recycle_distance > 0.0) || prev == NO_PREVIOUS {
        return false;
    }
    let old = previous_manifolds[prev];
    if old.len == 0u {
        return false;
    }
    let local = previous_locals[prev];
    let pose_a = poses[a];
    let tolerance = recycle_tolerance(params.recycle_distance, half_extents(a), half_extents(b));
    var points: array<vec4<f32>, MAX_MANIFOLD_POINTS>;
    if !recycle_points(local, old.len, pose_a, poses[b], pair_margin(a, b), tolerance, &points) {
        return false;
    }
    var manifold: GpuManifold;
    manifold.normal = vec4<f32>(quat_rotate(pose_a.rotation, local.normal.xyz), 0.0);
    manifold.body_a = a;
    manifold.body_b = b;
    manifold.kind = old.kind;
    manifold.feature = old.feature;
    manifold.previous = prev;
    manifold.len = old.len;
    manifold.recycled = 1u;
    for (var s = 0u; s < MAX_MANIFOLD_POINTS; s++) {
        var contact: GpuContact;
        if s < old.len {
            contact.position = vec4<f32>(points[s].xyz, 0.0);
            contact.depth = points[s].w;
            contact.id = previous_contacts[prev * MAX_MANIFOLD_POINTS + s].id;
        }
        contacts[k * MAX_MANIFOLD_POINTS + s] = contact;
    }
    manifolds[k] = manifold;
    return true;
}

// Pair k's manifold from the full test (separating axes, clipping, reduction).
fn collide_fresh(k: u32) {
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

// The pairs of this workgroup that need the full test, in the order their threads listed
// them (which varies from run to run and changes no result: each is written at its own index).
var<workgroup> fresh_pairs: array<u32, WORKGROUP_SIZE>;
// How many `fresh_pairs` holds.
var<workgroup> fresh_count: atomic<u32>;

// Whether the workgroup lists its fresh pairs first (above); off, each thread runs its own
// pair's full test. Off on CPU adapters (kernels::collide_cuboids::compact_fresh_pairs),
// where the two workgroup barriers were measured to cost more than the idle threads.
override COMPACT_FRESH_PAIRS: bool = true;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    if !COMPACT_FRESH_PAIRS {
        let k = thread_index(thread);
        if k < work.count && !try_recycle(k, pair_a[k], pair_b[k]) {
            collide_fresh(k);
        }
        return;
    }
    if thread.local == 0u {
        atomicStore(&fresh_count, 0u);
    }
    // Every thread reaches both barriers, so no thread returns early.
    workgroupBarrier();
    let k = thread_index(thread);
    if k < work.count && !try_recycle(k, pair_a[k], pair_b[k]) {
        fresh_pairs[atomicAdd(&fresh_count, 1u)] = k;
    }
    workgroupBarrier();
    if thread.local < atomicLoad(&fresh_count) {
        collide_fresh(fresh_pairs[thread.local]);
    }
}
