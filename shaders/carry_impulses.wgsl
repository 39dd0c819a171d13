// requires: common/indexing.wgsl common/box_pair.wgsl common/persistence.wgsl
// carry_impulses: one thread per manifold. It keeps the manifold in body A's frame for the
// next step, then gives each point last step's accumulated impulses by the rule of the CPU
// contact cache (tumble-solver's ContactCache::warm_start), claims in the same order:
//   1. under the same kind and reference feature (ids are only comparable then), the first
//      unclaimed old point with the point's feature id;
//   2. if the normal turned by less than the angle of PERSIST_NORMAL_COS in A's frame, each
//      point still unmatched takes the nearest unclaimed old point within PERSIST_DISTANCE
//      in A's frame (ids of points on exactly coincident edges flip under round-off while
//      the points stay put, as in aligned stacks).
// Points matched by neither start at zero, as collide_cuboids wrote them. This is the warm
// start's input. A recycled manifold keeps the frame-A record of the one it was recycled from
// (its anchors stay those of the manifold last computed, as in the CPU's contact cache) and
// inherits each point's impulses by id: ids, kind and feature are the old ones.

// This step's pair `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
// The bodies' poses the manifolds were found at.
@group(0) @binding(1) var<storage, read> poses: array<GpuPose>;
// This step's manifolds.
@group(0) @binding(2) var<storage, read> manifolds: array<GpuManifold>;
// Last step's manifolds.
@group(0) @binding(3) var<storage, read> previous_manifolds: array<GpuManifold>;
// Last step's contact points (with the solver's impulses).
@group(0) @binding(4) var<storage, read> previous_contacts: array<GpuContact>;
// Last step's manifolds in their body A's frame (`array<GpuLocalManifold>`).
@group(0) @binding(5) var<storage, read> previous_locals: array<GpuLocalManifold>;
// This step's contact points; impulses are written.
@group(0) @binding(6) var<storage, read_write> contacts: array<GpuContact>;
// This step's manifolds in body A's frame; written for every manifold with points.
@group(0) @binding(7) var<storage, read_write> locals: array<GpuLocalManifold>;

// Manifold k's normal, points and depths in the frame of body A at pose `a`, with B's frame
// (pose `b`) in A's.
fn local_manifold(k: u32, m: GpuManifold, a: GpuPose, b: GpuPose) -> GpuLocalManifold {
    // The conjugate: the inverse of a unit quaternion.
    let inverse = quat_conjugate(a.rotation);
    var out: GpuLocalManifold;
    out.normal = vec4<f32>(quat_rotate(inverse, m.normal.xyz), 0.0);
    for (var i = 0u; i < m.len; i++) {
        let point = contacts[k * MAX_MANIFOLD_POINTS + i];
        out.points[i] = vec4<f32>(quat_rotate(inverse, point.position.xyz - a.position.xyz), point.depth);
    }
    out.frame_rotation = quat_mul(inverse, b.rotation);
    out.frame_position = vec4<f32>(quat_rotate(inverse, b.position.xyz - a.position.xyz), 0.0);
    return out;
}

// Point `slot` takes old point `source`'s impulses.
fn inherit(slot: u32, source: u32) {
    let before = previous_contacts[source];
    contacts[slot].normal_impulse = before.normal_impulse;
    contacts[slot].friction_impulse = before.friction_impulse;
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let k = thread_index(thread);
    if k >= work.count {
        return;
    }
    let m = manifolds[k];
    if m.len == 0u {
        return;
    }
    var here = local_manifold(k, m, poses[m.body_a], poses[m.body_b]);
    if m.recycled != 0u {
        locals[k] = previous_locals[m.previous];
    } else {
        locals[k] = here;
    }
    if m.previous == NO_PREVIOUS {
        return;
    }
    let old = previous_manifolds[m.previous];
    if old.len == 0u {
        return;
    }
    let first_old = m.previous * MAX_MANIFOLD_POINTS;
    var claimed: array<bool, MAX_MANIFOLD_POINTS>;
    var matched: array<bool, MAX_MANIFOLD_POINTS>;
    if old.kind == m.kind && old.feature == m.feature {
        for (var i = 0u; i < m.len; i++) {
            let slot = k * MAX_MANIFOLD_POINTS + i;
            let id = contacts[slot].id;
            for (var j = 0u; j < old.len; j++) {
                if !claimed[j] && previous_contacts[first_old + j].id == id {
                    inherit(slot, first_old + j);
                    claimed[j] = true;
                    matched[i] = true;
                    break;
                }
            }
        }
    }
    var before = previous_locals[m.previous];
    if dot(here.normal.xyz, before.normal.xyz) < PERSIST_NORMAL_COS {
        return;
    }
    let limit = PERSIST_DISTANCE * PERSIST_DISTANCE;
    for (var i = 0u; i < m.len; i++) {
        if matched[i] {
            continue;
        }
        // The first of the nearest unclaimed old points (strict `<`), as the CPU's min_by.
        var nearest = old.len;
        var nearest_d2 = 0.0;
        for (var j = 0u; j < old.len; j++) {
            if claimed[j] {
                continue;
            }
            let d = before.points[j].xyz - here.points[i].xyz;
            let d2 = dot(d, d);
            if nearest == old.len || d2 < nearest_d2 {
                nearest = j;
                nearest_d2 = d2;
            }
        }
        if nearest < old.len && nearest_d2 <= limit {
            inherit(k * MAX_MANIFOLD_POINTS + i, first_old + nearest);
            claimed[nearest] = true;
        }
    }
}
