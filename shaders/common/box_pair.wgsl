// requires: common/quat.wgsl common/narrow_constants.wgsl
// Two boxes seen from the first one's frame (port of tumble-narrow's box_pair.rs): every SAT
// quantity is computed there, from the delta of the positions, so that digits two boxes far
// from the origin share cancel before rotating.

struct BoxPair {
    // Half extents of A (the frame's owner) and of B.
    ha: vec3<f32>,
    hb: vec3<f32>,
    // B's rotation in A's frame: column j is B's local axis j.
    rot: mat3x3<f32>,
    // Entry-wise absolute value of rot.
    abs_rot: mat3x3<f32>,
    // B's centre in A's frame.
    offset: vec3<f32>,
}

fn quat_conjugate(q: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(-q.xyz, q.w);
}

// The Hamilton product a b (apply b, then a).
fn quat_mul(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(
        a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz),
        a.w * b.w - dot(a.xyz, b.xyz),
    );
}

fn abs_mat3(m: mat3x3<f32>) -> mat3x3<f32> {
    return mat3x3<f32>(abs(m[0]), abs(m[1]), abs(m[2]));
}

fn box_pair_from_parts(ha: vec3<f32>, hb: vec3<f32>, rot: mat3x3<f32>, offset: vec3<f32>) -> BoxPair {
    return BoxPair(ha, hb, rot, abs_mat3(rot), offset);
}

fn make_box_pair(ha: vec3<f32>, pose_a: GpuPose, hb: vec3<f32>, pose_b: GpuPose) -> BoxPair {
    let inverse_a = quat_conjugate(pose_a.rotation);
    let rot = quat_to_mat3(quat_mul(inverse_a, pose_b.rotation));
    let delta = pose_b.position.xyz - pose_a.position.xyz;
    return box_pair_from_parts(ha, hb, rot, quat_rotate(inverse_a, delta));
}

// The same pair seen from B's frame, roles exchanged.
fn swapped(p: BoxPair) -> BoxPair {
    let rot_t = transpose(p.rot);
    return box_pair_from_parts(p.hb, p.ha, rot_t, -(rot_t * p.offset));
}

// A point of B's frame in A's frame.
fn b_to_a(p: BoxPair, v: vec3<f32>) -> vec3<f32> {
    return p.rot * v + p.offset;
}

// A point of A's frame in B's frame.
fn a_to_b(p: BoxPair, v: vec3<f32>) -> vec3<f32> {
    return transpose(p.rot) * (v - p.offset);
}

fn max3(v: vec3<f32>) -> f32 {
    return max(v.x, max(v.y, v.z));
}

// The length rounding errors scale with: the largest half extent of either box.
fn noise_scale(p: BoxPair) -> f32 {
    return max(max3(p.ha), max3(p.hb));
}

// The length feature choices scale with: the smaller box's largest half extent.
fn feature_scale(p: BoxPair) -> f32 {
    return min(max3(p.ha), max3(p.hb));
}

// Local vertex v of a box: +h on axis k when bit k of v is set (the cuboid convention).
fn box_vertex(h: vec3<f32>, v: u32) -> vec3<f32> {
    let bits = vec3<u32>(v, v >> 1u, v >> 2u) & vec3<u32>(1u);
    return select(-h, h, bits == vec3<u32>(1u));
}

// The two end vertices of edge e (along axis e / 4): bit "lo" of the other two axes is e's
// bit 0, bit "hi" its bit 1, as in CUBOID_EDGES.
fn edge_vertices(e: u32) -> vec2<u32> {
    let axis = e / 4u;
    let lo = min((axis + 1u) % 3u, (axis + 2u) % 3u);
    let hi = max((axis + 1u) % 3u, (axis + 2u) % 3u);
    let v0 = ((e & 1u) << lo) | (((e >> 1u) & 1u) << hi);
    return vec2<u32>(v0, v0 | (1u << axis));
}

// The face of a box whose outward normal is most aligned with local direction dir
// (ties: lower axis; on an axis, the positive face unless dir is negative).
fn best_face(dir: vec3<f32>) -> u32 {
    let a = abs(dir);
    var axis = 2u;
    if a.x >= a.y && a.x >= a.z {
        axis = 0u;
    } else if a.y >= a.z {
        axis = 1u;
    }
    return 2u * axis + u32(dir[axis] < 0.0);
}

// The point of a box (local frame) nearest to p.
fn box_closest_point(h: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    return min(max(p, -h), h);
}

fn unit_axis(i: u32) -> vec3<f32> {
    var v = vec3<f32>(0.0);
    v[i] = 1.0;
    return v;
}

fn mat_row(m: mat3x3<f32>, i: u32) -> vec3<f32> {
    return vec3<f32>(m[0][i], m[1][i], m[2][i]);
}
