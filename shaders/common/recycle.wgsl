// requires: common/layout.wgsl common/box_pair.wgsl
// Contact recycling (port of tumble-solver's recycle.rs, `CachedManifold::recycle`): a pair
// whose bodies barely moved relative to each other since its manifold was last computed keeps
// that manifold, its points attached to the same material points of both boxes, instead of
// running the separating axis test and the clipping again. The anchors are those of the
// CPU's contact cache, rebuilt from a `GpuLocalManifold`: point i's anchor on A is its point
// moved half its depth along the normal, its anchor on B the point moved half the depth back,
// carried into B's frame by the relative frame stored with it. Every quantity is formed in A's
// frame at this step's poses (distances and angles are the same in any frame).

// Cosine of the largest turn of the normal, seen from A against seen from B
// (tumble_solver::RECYCLE_NORMAL_COS: one degree).
override RECYCLE_NORMAL_COS: f32;
// The largest slide as a fraction of the pair's smallest half extent
// (tumble_solver::RECYCLE_SIZE_FRACTION).
override RECYCLE_SIZE_FRACTION: f32;

// The largest slide of a recycled point for boxes of half extents `ha` and `hb` when the world
// allows `distance` (tumble_solver::recycle_tolerance).
fn recycle_tolerance(distance: f32, ha: vec3<f32>, hb: vec3<f32>) -> f32 {
    let smallest = min(min(min(ha.x, ha.y), ha.z), min(min(hb.x, hb.y), hb.z));
    return min(distance, RECYCLE_SIZE_FRACTION * smallest);
}

// Last step's manifold `local` (`len` points) moved with the bodies to `pose_a` and `pose_b`,
// into `out` (xyz: the world point midway between the anchors, w: the depth), when it may be
// reused: the normal turned by less than a degree relative to B, every point's separation kept
// its sign and stays within `margin`, and every B anchor slid across the normal by at most
// `tolerance` from its A anchor. False (and `out` unspecified) when the pair needs a fresh
// manifold.
fn recycle_points(
    local: GpuLocalManifold,
    len: u32,
    pose_a: GpuPose,
    pose_b: GpuPose,
    margin: f32,
    tolerance: f32,
    out: ptr<function, array<vec4<f32>, MAX_MANIFOLD_POINTS>>,
) -> bool {
    if len == 0u || !(tolerance > 0.0) {
        return false;
    }
    // B's frame in A's frame now, and when the manifold was found.
    let inverse_a = quat_conjugate(pose_a.rotation);
    let rotation = quat_mul(inverse_a, pose_b.rotation);
    let offset = quat_rotate(inverse_a, pose_b.position.xyz - pose_a.position.xyz);
    let back = quat_conjugate(local.frame_rotation);
    let normal = local.normal.xyz;
    // The normal as B carries it (A's normal in B's frame then, turned with B now).
    let normal_b = quat_rotate(rotation, quat_rotate(back, normal));
    if !(dot(normal, normal_b) >= RECYCLE_NORMAL_COS) {
        return false;
    }
    let tolerance2 = tolerance * tolerance;
    for (var i = 0u; i < len; i++) {
        let point = local.points[i];
        let half = normal * (0.5 * point.w);
        let on_a = point.xyz + half;
        let anchor_b = quat_rotate(back, point.xyz - half - local.frame_position.xyz);
        let on_b = quat_rotate(rotation, anchor_b) + offset;
        let gap = on_b - on_a;
        let separation = dot(gap, normal);
        // A point that started or stopped overlapping may bring other points with it; one
        // beyond the margin would not be reported by a fresh test.
        let overlapped = point.w >= 0.0;
        if (separation <= 0.0) != overlapped || separation > margin {
            return false;
        }
        let slide = gap - normal * separation;
        if !(dot(slide, slide) <= tolerance2) {
            return false;
        }
        let middle = 0.5 * (on_a + on_b);
        (*out)[i] = vec4<f32>(quat_rotate(pose_a.rotation, middle) + pose_a.position.xyz, -separation);
    }
    return true;
}
