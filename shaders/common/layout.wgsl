// requires: common/constants.wgsl
// Structs shared with the host. Each has a #[repr(C)] twin of the same name in
// crates/tumble-gpu/src/layout.rs; the layout test compares sizes and field offsets with
// naga's layouter. No vec3 in these structs: a vec3 is 16-byte aligned but 12 bytes long,
// which host structs do not reproduce, so padding is always spelled out.

// A body's pose. 32 bytes.
struct GpuPose {
    // World position of the centre of mass; w unused (0).
    position: vec4<f32>,
    // Unit quaternion (x, y, z, w), w the scalar part.
    rotation: vec4<f32>,
}

// A body's velocity. 32 bytes.
struct GpuVelocity {
    // Linear velocity (m/s); w unused.
    linear: vec4<f32>,
    // Angular velocity (rad/s, world frame); w unused.
    angular: vec4<f32>,
}

// A body's cuboid and flags. 16 bytes.
struct GpuShape {
    // Half extents along the local axes (m).
    hx: f32,
    hy: f32,
    hz: f32,
    // Bit set of BODY_* flags (see GpuShape in layout.rs).
    flags: u32,
}

// A world-space AABB. 32 bytes.
struct GpuAabb {
    // Lower corner; w unused.
    min: vec4<f32>,
    // Upper corner; w unused.
    max: vec4<f32>,
}

// Arguments of dispatch_workgroups_indirect, padded to 16 bytes.
struct DispatchArgs {
    x: u32,
    y: u32,
    z: u32,
    _pad: u32,
}

// A GPU-side count of work items and the dispatch size that covers it. 32 bytes.
struct WorkList {
    // Items to process (an append count clamped to the capacity).
    count: u32,
    // Items the producer tried to append; greater than capacity means overflow.
    requested: u32,
    // Slots in the item buffer.
    capacity: u32,
    _pad: u32,
    // Workgroups covering one thread per item (folded past the per-dimension limit), which
    // is also one workgroup per tile of WORKGROUP_SIZE items.
    groups: DispatchArgs,
}

// Parameters of update_aabbs. 16 bytes.
struct UpdateAabbsParams {
    // Bodies.
    count: u32,
    // Distance every AABB grows by on each side (m): the speculative contact margin.
    margin: f32,
    // Time step (s): AABBs also sweep by velocity * dt.
    dt: f32,
    _pad: u32,
}

// Parameters of one radix sort pass. 16 bytes.
struct RadixPassParams {
    // Bit offset of the digit this pass sorts on.
    shift: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

// Parameters of sweep_pairs. 16 bytes.
struct SweepParams {
    // Bodies.
    body_count: u32,
    // Slots in the pair buffers.
    pair_capacity: u32,
    // Boxes longer than this on the sweep axis (m) are paired by long_pairs (sweep.wgsl).
    long_extent: f32,
    // Bits of the largest world index, which lead the sort keys (0 for one world).
    world_bits: u32,
}

// The sweep axis and the statistics it was chosen from. 32 bytes.
struct SweepAxis {
    // 0, 1 or 2: the axis of largest centre variance.
    axis: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    // Centre variance along x, y, z (m^2); w unused.
    variance: vec4<f32>,
}

// Parameters of collide_cuboids. 16 bytes.
struct NarrowParams {
    // Base speculative margin (m): points this far apart are still reported.
    margin: f32,
    // Time step (s): the margin grows by how far a pair can close in one step.
    dt: f32,
    // Largest slide of a recycled point across the normal (m); 0: every manifold afresh.
    recycle_distance: f32,
    _pad0: u32,
}

// One contact point of a manifold. 48 bytes.
struct GpuContact {
    // World point midway between the surfaces; w unused.
    position: vec4<f32>,
    // Accumulated friction impulse (world, N s), carried between steps; w: the normal impulse
    // applied over the last step (store_impulses writes it for the host's reads; nothing on
    // the GPU reads it).
    friction_impulse: vec4<f32>,
    // Overlap along the normal (m): positive when overlapping.
    depth: f32,
    // Feature id: the same while the same features touch.
    id: u32,
    // Accumulated normal impulse (N s), carried between steps.
    normal_impulse: f32,
    _pad: u32,
}

// The manifold of candidate pair k; its points are contacts[k * MAX_MANIFOLD_POINTS ..]. 48 bytes.
struct GpuManifold {
    // Unit normal from A to B; w unused.
    normal: vec4<f32>,
    // The pair's bodies, body_a < body_b.
    body_a: u32,
    body_b: u32,
    // MANIFOLD_FACE_A, MANIFOLD_FACE_B or MANIFOLD_EDGE.
    kind: u32,
    // Reference face, or packed edge pair (edge_a * 12 + edge_b), or vertex feature.
    feature: u32,
    // Valid points, 0 (no contact) to MAX_MANIFOLD_POINTS.
    len: u32,
    // Index of this pair's manifold last step, or NO_PREVIOUS.
    previous: u32,
    // 1 when last step's manifold was reused (collide_cuboids' try_recycle), else 0.
    recycled: u32,
    _pad0: u32,
}

// A manifold in body A's frame at the poses it was found at, kept per pair slot so that
// the next step's carry_impulses can match points whose feature ids changed by where they are
// on A (the CPU contact cache keeps the same), and so that collide_cuboids can reuse it while
// the bodies barely moved relative to each other (the anchors of tumble-solver's
// CachedManifold follow from the points, their depths and B's frame). A recycled manifold
// keeps the one it was recycled from: it stays that of the manifold last computed. 112 bytes.
struct GpuLocalManifold {
    // The manifold normal in A's frame; w unused.
    normal: vec4<f32>,
    // Each point in A's frame; w: its depth. Slots past the manifold's len zero.
    points: array<vec4<f32>, MAX_MANIFOLD_POINTS>,
    // B's rotation in A's frame (x, y, z, w).
    frame_rotation: vec4<f32>,
    // B's origin in A's frame; w unused.
    frame_position: vec4<f32>,
}

// A body's AABB in sweep order, coordinates permuted so the sweep axis comes first (then
// the axis after it, then the one after that): the sweep reads one contiguous record per
// candidate, and neighbouring threads read neighbouring records. 32 bytes.
struct GpuSweepBox {
    // Lower corner, sweep axis first.
    lo_0: f32,
    lo_1: f32,
    lo_2: f32,
    // The body's index.
    body: u32,
    // Upper corner, sweep axis first.
    hi_0: f32,
    hi_1: f32,
    hi_2: f32,
    // The body's GpuShape.flags.
    flags: u32,
}

// A body's collision groups (GpuCollisionGroups in layout.rs): two bodies pair only when each
// one's memberships meet the other's filter. 8 bytes.
struct GpuCollisionGroups {
    // The groups the body belongs to, one bit each.
    memberships: u32,
    // The groups the body collides with, one bit each (`filter` is a keyword).
    filter_bits: u32,
}

// Where a manifold in contact sits: its pair slot and its first point in the dense list.
// 8 bytes.
struct GpuTouching {
    // Index of the pair (and of its manifold in the per-pair arrays).
    slot: u32,
    // Index of its first point among the dense points.
    first_point: u32,
}

// Totals of the dense contact list. 16 bytes.
struct TouchingCounts {
    // Manifolds in contact.
    manifolds: u32,
    // Their points.
    points: u32,
    _pad0: u32,
    _pad1: u32,
}

// Parameters of scatter_impulses. 16 bytes.
struct ScatterParams {
    // Dense manifolds to scatter.
    count: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

// A pair that began or ended touching, or one that touches. 32 bytes.
struct GpuContactEvent {
    // EVENT_BEGIN, EVENT_END or EVENT_TOUCHING.
    kind: u32,
    // The pair's bodies (dense indices at the step), body_a < body_b.
    body_a: u32,
    body_b: u32,
    // The pair's slot in its step's pair list.
    slot: u32,
    // xyz: the contact point (the points' mean weighted by their normal impulses, or their
    // plain mean when none pushed); w: the manifold's normal impulse over the step.
    point: vec4<f32>,
}
