// Constants shared with the host. Their values are defined once, in
// crates/tumble-gpu/src/constants.rs (or in the crate that owns the concept, such as the
// narrow phase's tolerances), and supplied at pipeline creation; none has a default here, so
// a pipeline built without them fails instead of silently using a stale number.
// (MAX_MANIFOLD_POINTS, MAX_CLIP_VERTICES and CUBOID_FACES are array sizes and tables, which
// WGSL needs as consts: they come in the generated prelude.)

// Threads per workgroup of every kernel.
override WORKGROUP_SIZE: u32;
// Key bits sorted per radix pass, and the bucket count 2^RADIX_BITS.
override RADIX_BITS: u32;
override RADIX: u32;
// Dispatches wider than this many workgroups fold into the y dimension.
override MAX_WORKGROUPS_PER_DIMENSION: u32;
// GpuShape.flags bit of a body that never moves.
override BODY_STATIC: u32;
// GpuShape.flags holds the body's world index from this bit up.
override BODY_WORLD_SHIFT: u32;
// remap_pairs: flag of a body whose world's pairs are dropped.
override REMAP_DROPPED: u32;
// GpuManifold.previous when the pair had no manifold last step.
override NO_PREVIOUS: u32;
// GpuManifold.kind codes.
override MANIFOLD_FACE_A: u32;
override MANIFOLD_FACE_B: u32;
override MANIFOLD_EDGE: u32;
