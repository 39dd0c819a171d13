// The narrow phase's tolerances and feature-id layout, owned by crates/tumble-narrow
// (tolerance.rs, feature_id.rs, collide.rs) and handed to the kernel as override values, so
// the GPU port cannot drift from the CPU algorithm it mirrors.

override PARALLEL_EDGE_SIN_SQ: f32;
override FACE_B_REL_TOL: f32;
override FACE_B_ABS_TOL: f32;
override EDGE_REL_TOL: f32;
override EDGE_ABS_TOL: f32;
override FACE_LIKE_EDGE_COS: f32;
override FACE_LIKE_MAX_DEPTH: f32;
override HYSTERESIS_REL_TOL: f32;
override HYSTERESIS_ABS_TOL: f32;
override WITNESS_TOL: f32;
// tumble-geometry's segment closest-points thresholds.
override SEGMENT_DEGENERATE_RATIO: f32;
override SEGMENT_PARALLEL_SIN_SQ: f32;
// Contact id packing.
override ID_KIND_FACE_A: u32;
override ID_KIND_FACE_B: u32;
override ID_KIND_EDGE: u32;
override ID_KIND_VERTEX: u32;
override ID_KIND_SHIFT: u32;
override ID_REFERENCE_SHIFT: u32;
override ID_INCIDENT_SHIFT: u32;
override ID_FIELD_SHIFT: u32;
override SIDE_LABEL_BASE: u32;
// Manifold.feature of vertex contacts: B's vertex v is EDGE_PAIR_COUNT + v, A's is
// VERTEX_OF_A_FEATURE + v.
override EDGE_PAIR_COUNT: u32;
override VERTEX_OF_A_FEATURE: u32;
