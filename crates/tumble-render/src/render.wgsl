// tumble-render: boxes instanced from the body buffers, a shadow map, contact dots (filled
// with their graph colour on request), normals, AABB outlines and pair lines. The renderer composes this file after shaders/common/layout.wgsl (and what it
// requires), so the storage structs (GpuPose, GpuShape, GpuManifold, GpuContact) and
// BODY_STATIC and MAX_MANIFOLD_POINTS are the physics step's own, read as the step left them;
// it also prepends GRAPH_COLOUR_SLOTS (the solver's graph colours and the overflow set).

struct Frame {
    // World to clip space of the camera (depth 0..1).
    view_proj: mat4x4<f32>,
    // World to clip space of the light's orthographic shadow camera.
    light_view_proj: mat4x4<f32>,
    // Unit vector towards the light; w: 1 with shadows, 0 without.
    light_dir: vec4<f32>,
    // Width, height (pixels), contact dot radius (pixels), normal length (m).
    viewport: vec4<f32>,
    // x: 1 to fill the contact dots with their manifold's graph colour. y: 1 when the pair
    // lines' bodies are the `w` records of `manifolds` from index `z` (the host's list of
    // the broad phase's pairs), 0 when they are the manifold slots in use (on the GPU each
    // slot is one candidate pair of the broad phase).
    flags: vec4<u32>,
}

// Body kind codes: tumble-gpu's GpuBody.kind values (solver/constants.rs), supplied at
// pipeline creation as every solver kernel gets them.
override BODY_FIXED: u32;
override BODY_DYNAMIC: u32;
override BODY_KINEMATIC: u32;

// Overridden by the renderer with its palette (linear 0..1 values written as they are).
override fixed_r: f32 = 0.56;
override fixed_g: f32 = 0.57;
override fixed_b: f32 = 0.60;
override dynamic_r: f32 = 0.96;
override dynamic_g: f32 = 0.55;
override dynamic_b: f32 = 0.16;
override kinematic_r: f32 = 0.22;
override kinematic_g: f32 = 0.50;
override kinematic_b: f32 = 0.96;
override sleeping_r: f32 = 0.62;
override sleeping_g: f32 = 0.50;
override sleeping_b: f32 = 0.40;
override dot_r: f32 = 0.95;
override dot_g: f32 = 0.05;
override dot_b: f32 = 0.75;
override aabb_r: f32 = 0.05;
override aabb_g: f32 = 0.55;
override aabb_b: f32 = 0.45;
override pair_r: f32 = 0.35;
override pair_g: f32 = 0.20;
override pair_b: f32 = 0.85;

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> poses: array<GpuPose>;
@group(0) @binding(2) var<storage, read> shapes: array<GpuShape>;
@group(0) @binding(3) var<storage, read> kinds: array<u32>;
@group(0) @binding(4) var<storage, read> work: array<u32>;
@group(0) @binding(5) var<storage, read> manifolds: array<GpuManifold>;
@group(0) @binding(6) var<storage, read> contacts: array<GpuContact>;
// The solver's ColorSlot per manifold slot: x the colour, y a proposal nothing here reads.
@group(0) @binding(7) var<storage, read> colors: array<vec2<u32>>;
// The dot fill of each graph colour, then of the overflow set.
@group(0) @binding(8) var<uniform> graph_colours: array<vec4<f32>, GRAPH_COLOUR_SLOTS>;

@group(1) @binding(0) var shadow_map: texture_depth_2d;
@group(1) @binding(1) var shadow_sampler: sampler_comparison;

fn rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

fn unit(axis: u32) -> vec3<f32> {
    var e = vec3<f32>(0.0);
    e[axis] = 1.0;
    return e;
}

struct BoxVertex {
    world: vec3<f32>,
    normal: vec3<f32>,
    // Position on the face (m) and the face's half sizes, for the edge lines.
    face: vec4<f32>,
}

// Vertex `v` (0..36) of body `i`'s box: 6 faces of 2 triangles, no vertex buffer.
fn box_vertex(i: u32, v: u32) -> BoxVertex {
    let f = v / 6u;
    let c = v % 6u;
    var corners = array<vec2<f32>, 6>(
        vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(1.0, 1.0),
        vec2(-1.0, -1.0), vec2(1.0, 1.0), vec2(-1.0, 1.0),
    );
    let ab = corners[c];
    let axis = f / 2u;
    let sign = select(-1.0, 1.0, f % 2u == 0u);
    let ua = (axis + 1u) % 3u;
    let va = (axis + 2u) % 3u;
    let s = shapes[i];
    let h = vec3<f32>(s.hx, s.hy, s.hz);
    let local = (unit(axis) * sign + unit(ua) * ab.x + unit(va) * ab.y) * h;
    let pose = poses[i];
    var out: BoxVertex;
    out.world = pose.position.xyz + rotate(pose.rotation, local);
    out.normal = rotate(pose.rotation, unit(axis) * sign);
    out.face = vec4(ab.x * h[ua], ab.y * h[va], h[ua], h[va]);
    return out;
}

fn body_colour(i: u32) -> vec3<f32> {
    let kind = kinds[i];
    if kind == BODY_FIXED {
        return vec3(fixed_r, fixed_g, fixed_b);
    }
    if kind == BODY_KINEMATIC {
        return vec3(kinematic_r, kinematic_g, kinematic_b);
    }
    // A dynamic body flagged static is out of the step: asleep.
    if (shapes[i].flags & BODY_STATIC) != 0u {
        return vec3(sleeping_r, sleeping_g, sleeping_b);
    }
    return vec3(dynamic_r, dynamic_g, dynamic_b);
}

struct BoxOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) face: vec4<f32>,
    @location(3) @interpolate(flat) colour: vec3<f32>,
}

@vertex
fn vs_box(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> BoxOut {
    let b = box_vertex(i, v);
    var out: BoxOut;
    out.clip = frame.view_proj * vec4(b.world, 1.0);
    out.world = b.world;
    out.normal = b.normal;
    out.face = b.face;
    out.colour = body_colour(i);
    return out;
}

@vertex
fn vs_shadow(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> @builtin(position) vec4<f32> {
    return frame.light_view_proj * vec4(box_vertex(i, v).world, 1.0);
}

// 1 in light, 0 in shadow (3x3 percentage-closer filter); 1 outside the shadow map.
fn lit_fraction(world: vec3<f32>, normal: vec3<f32>) -> f32 {
    if frame.light_dir.w == 0.0 {
        return 1.0;
    }
    let clip = frame.light_view_proj * vec4(world, 1.0);
    let ndc = clip.xyz / clip.w;
    let uv = vec2(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2(0.0)) || any(uv > vec2(1.0)) || ndc.z > 1.0 {
        return 1.0;
    }
    let texel = 1.0 / vec2<f32>(textureDimensions(shadow_map));
    // Slope-scaled bias against acne on faces lit at grazing angles.
    let cosine = clamp(dot(normal, frame.light_dir.xyz), 0.0, 1.0);
    let bias = 0.0015 + 0.004 * (1.0 - cosine);
    var sum = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let o = vec2(f32(dx), f32(dy)) * texel;
            sum += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + o, ndc.z - bias);
        }
    }
    return sum / 9.0;
}

@fragment
fn fs_box(in: BoxOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let lambert = max(dot(n, frame.light_dir.xyz), 0.0);
    let light = lit_fraction(in.world, n);
    // Sky above, ground bounce below: faces pointing down are darker than side faces.
    let ambient = 0.36 + 0.10 * n.y;
    var colour = in.colour * (ambient + 0.58 * lambert * light);
    // Dark lines along the box edges, about one pixel wide at any distance.
    let to_edge = in.face.zw - abs(in.face.xy);
    let px = fwidth(in.face.xy);
    let edge = min(to_edge.x / max(px.x, 1e-6), to_edge.y / max(px.y, 1e-6));
    colour *= mix(0.55, 1.0, clamp(edge - 0.5, 0.0, 1.0));
    return vec4(colour, 1.0);
}

struct DotOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) offset: vec2<f32>,
    @location(1) @interpolate(flat) fill: vec3<f32>,
}

// The fill of the dots of manifold slot `k`: its graph colour when asked for and known, the
// palette's contact colour otherwise.
fn dot_fill(k: u32) -> vec3<f32> {
    if frame.flags.x != 0u && k < arrayLength(&colors) {
        let c = colors[k].x;
        if c < GRAPH_COLOUR_SLOTS {
            return graph_colours[c].rgb;
        }
    }
    return vec3(dot_r, dot_g, dot_b);
}

// Contact point `p` of manifold slot `k`, instance `k * MAX_MANIFOLD_POINTS + p`; false past the
// manifolds in use or past the manifold's points.
fn contact_point(instance: u32, point: ptr<function, vec3<f32>>, normal: ptr<function, vec3<f32>>) -> bool {
    let k = instance / MAX_MANIFOLD_POINTS;
    let p = instance % MAX_MANIFOLD_POINTS;
    if k >= work[0] || p >= manifolds[k].len {
        return false;
    }
    *point = contacts[instance].position.xyz;
    *normal = manifolds[k].normal.xyz;
    return true;
}

const OFF_SCREEN: vec4<f32> = vec4(2.0, 2.0, 2.0, 1.0);

@vertex
fn vs_dot(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> DotOut {
    var out: DotOut;
    var point: vec3<f32>;
    var normal: vec3<f32>;
    if !contact_point(i, &point, &normal) {
        out.clip = OFF_SCREEN;
        return out;
    }
    var corners = array<vec2<f32>, 6>(
        vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(1.0, 1.0),
        vec2(-1.0, -1.0), vec2(1.0, 1.0), vec2(-1.0, 1.0),
    );
    let c = corners[v];
    // One pixel more than the radius, for the outline.
    let radius = frame.viewport.z + 1.0;
    let clip = frame.view_proj * vec4(point, 1.0);
    if clip.w <= 0.0 {
        out.clip = OFF_SCREEN;
        return out;
    }
    let pixels = 2.0 / frame.viewport.xy;
    out.clip = vec4(clip.xy + c * radius * pixels * clip.w, 0.0, clip.w);
    out.offset = c * radius;
    out.fill = dot_fill(i / MAX_MANIFOLD_POINTS);
    return out;
}

@fragment
fn fs_dot(in: DotOut) -> @location(0) vec4<f32> {
    let r = length(in.offset);
    if r > frame.viewport.z + 1.0 {
        discard;
    }
    if r > frame.viewport.z - 0.5 {
        return vec4(0.1, 0.1, 0.1, 1.0);
    }
    return vec4(in.fill, 1.0);
}

@vertex
fn vs_normal(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> @builtin(position) vec4<f32> {
    var point: vec3<f32>;
    var normal: vec3<f32>;
    if !contact_point(i, &point, &normal) {
        return OFF_SCREEN;
    }
    let end = point + normal * frame.viewport.w * f32(v);
    let clip = frame.view_proj * vec4(end, 1.0);
    return vec4(clip.xy, 0.0, clip.w);
}

@fragment
fn fs_normal() -> @location(0) vec4<f32> {
    return vec4(0.1, 0.75, 0.2, 1.0);
}

// Vertex `v` (0..24) of the outline of body `i`'s world bounds: edge v / 2 runs along axis
// (v / 2) / 4, at the corner (v / 2) % 4 of the other two axes, from its low end (v even) to
// its high end.
@vertex
fn vs_aabb(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> @builtin(position) vec4<f32> {
    let s = shapes[i];
    let q = poses[i].rotation;
    // Half extents of the rotated box along the world axes: the sum of its axes' extents.
    let half = abs(rotate(q, vec3(s.hx, 0.0, 0.0))) + abs(rotate(q, vec3(0.0, s.hy, 0.0)))
        + abs(rotate(q, vec3(0.0, 0.0, s.hz)));
    let e = v / 2u;
    let axis = e / 4u;
    var corner = vec3<f32>(0.0);
    corner[axis] = select(-1.0, 1.0, v % 2u == 1u);
    corner[(axis + 1u) % 3u] = select(-1.0, 1.0, (e & 1u) != 0u);
    corner[(axis + 2u) % 3u] = select(-1.0, 1.0, (e & 2u) != 0u);
    let world = poses[i].position.xyz + corner * half;
    let clip = frame.view_proj * vec4(world, 1.0);
    return vec4(clip.xy, 0.0, clip.w);
}

@fragment
fn fs_aabb() -> @location(0) vec4<f32> {
    return vec4(aabb_r, aabb_g, aabb_b, 1.0);
}

// End `v` (0 or 1) of the line between the centres of candidate pair `k`'s two bodies (see
// Frame.flags); off screen past the pairs.
@vertex
fn vs_pair(@builtin(vertex_index) v: u32, @builtin(instance_index) k: u32) -> @builtin(position) vec4<f32> {
    let host_list = frame.flags.y == 1u;
    let count = select(work[0], frame.flags.w, host_list);
    if k >= count {
        return OFF_SCREEN;
    }
    let slot = select(k, frame.flags.z + k, host_list);
    let body = select(manifolds[slot].body_a, manifolds[slot].body_b, v == 1u);
    if body >= arrayLength(&poses) {
        return OFF_SCREEN;
    }
    let clip = frame.view_proj * vec4(poses[body].position.xyz, 1.0);
    return vec4(clip.xy, 0.0, clip.w);
}

@fragment
fn fs_pair() -> @location(0) vec4<f32> {
    return vec4(pair_r, pair_g, pair_b, 1.0);
}
