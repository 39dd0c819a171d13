// Contact persistence tolerances, tumble-solver's contact-cache values supplied by the host
// (crates/tumble-gpu/src/constants.rs): how far a point may move in body A's frame, and how
// far the normal may turn, for a point whose feature id changed to keep last step's impulse.

// Farthest a point may move in A's frame and still inherit an impulse by position (m).
override PERSIST_DISTANCE: f32;
// Smallest cosine between last step's normal and this step's, in A's frame, for any
// inheritance by position.
override PERSIST_NORMAL_COS: f32;
