// requires: common/indexing.wgsl common/layout.wgsl common/ray_types.wgsl
// cast_rays: one thread per ray finds the ray's closest hit among every body's box, as the
// CPU's `World::cast_ray` does (tumble-geometry's ray.rs): the ray taken into the box's frame
// by the inverse of its pose, the slab test on the box's half extents, the hit at the start
// of the overlap with the outward normal of the slab entered last (zero when the ray starts
// inside). Each thread walks the bodies in dense order and keeps a hit only when strictly
// earlier, so of two bodies hit at the same time the one of the lower dense index wins, the
// CPU's tie rule. The arithmetic follows the CPU's operation by operation (nalgebra's
// quaternion rotation and cross product, a division per slab); a compiler may still fuse a
// multiply and an add, so times agree to rounding, not always bit for bit.

@group(0) @binding(0) var<uniform> params: RayCastParams;
// The batch, one thread each.
@group(0) @binding(1) var<storage, read> rays: array<GpuRay>;
// The world's poses, dense order (the step's own buffer).
@group(0) @binding(2) var<storage, read> poses: array<GpuPose>;
// The world's shapes, dense order (the step's own buffer).
@group(0) @binding(3) var<storage, read> shapes: array<GpuShape>;
// Output: one closest hit per ray.
@group(0) @binding(4) var<storage, read_write> hits: array<GpuRayHit>;

// a x b, each component written as nalgebra computes it.
fn cross_in_order(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

// `v` rotated by the unit quaternion `q` (x, y, z, w) as nalgebra does it:
// t = 2 (q.xyz x v), then (t q.w + q.xyz x t) + v.
fn rotate_in_order(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = cross_in_order(q.xyz, v) * 2.0;
    return t * q.w + cross_in_order(q.xyz, t) + v;
}

// The closest hit so far: time, body, normal.
struct Best {
    toi: f32,
    body: u32,
    normal: vec3<f32>,
    hit: bool,
}

// Slab test of ray `o + t d` (box frame) against the box `|x_k| <= h_k`, t in [0, max_toi]:
// `x` the entry time, `y` the axis entered last plus one (0: started inside), `z` the sign
// of its outward normal; `w` 1 on a hit, 0 on a miss.
fn slab_test(o: vec3<f32>, d: vec3<f32>, h: vec3<f32>, max_toi: f32) -> vec4<f32> {
    var enter = 0.0;
    var exit = max_toi;
    var axis = 0.0;
    var sign = 0.0;
    for (var k = 0u; k < 3u; k++) {
        let lo = -h[k];
        let hi = h[k];
        if d[k] == 0.0 {
            if !(lo <= o[k] && o[k] <= hi) {
                return vec4<f32>(0.0);
            }
            continue;
        }
        let t_min = (lo - o[k]) / d[k];
        let t_max = (hi - o[k]) / d[k];
        var near = t_max;
        var far = t_min;
        var s = 1.0;
        if t_min <= t_max {
            near = t_min;
            far = t_max;
            s = -1.0;
        }
        if near > enter {
            enter = near;
            axis = f32(k + 1u);
            sign = s;
        }
        if far < exit {
            exit = far;
        }
        if enter > exit {
            return vec4<f32>(0.0);
        }
    }
    return vec4<f32>(enter, axis, sign, 1.0);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let r = thread_index(thread);
    if r >= params.rays {
        return;
    }
    let origin = rays[r].origin.xyz;
    let dir = rays[r].dir.xyz;
    var best = Best(params.max_toi, 0u, vec3<f32>(0.0), false);
    for (var b = 0u; b < params.bodies; b++) {
        let pose = poses[b];
        let inverse = vec4<f32>(-pose.rotation.xyz, pose.rotation.w);
        let o = rotate_in_order(inverse, origin - pose.position.xyz);
        let d = rotate_in_order(inverse, dir);
        let s = shapes[b];
        let found = slab_test(o, d, vec3<f32>(s.hx, s.hy, s.hz), params.max_toi);
        if found.w == 0.0 {
            continue;
        }
        // Strictly earlier only: a tie keeps the lower dense index.
        if !best.hit || found.x < best.toi {
            var normal = vec3<f32>(0.0);
            if found.y > 0.0 {
                var e = vec3<f32>(0.0);
                e[u32(found.y) - 1u] = found.z;
                normal = rotate_in_order(pose.rotation, e);
            }
            best = Best(found.x, b, normal, true);
        }
    }
    var out: GpuRayHit;
    out.normal = vec4<f32>(best.normal, 0.0);
    out.toi = best.toi;
    out.body = best.body;
    out.hit = select(0u, 1u, best.hit);
    hits[r] = out;
}
