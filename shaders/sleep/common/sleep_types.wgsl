// Structs of the sleep kernels shared with the host. Each has a #[repr(C)] twin of the same
// name in crates/tumble-gpu/src/sleep/layout.rs, compared field by field with naga's layouter
// in tests/tests/gpu_layout.rs. As in layout.wgsl: no vec3, padding spelled out.

// The sleep stage's per-world settings. 32 bytes.
struct SleepParams {
    // Bodies in the world.
    body_count: u32,
    // Time step (s): what a resting body's rest time grows by per step.
    dt: f32,
    // Kinematic bodies (entries of the kinematic list).
    kinematic_count: u32,
    _pad0: u32,
    // Workgroups (x, y) of a dispatch over every body, as the host folds them.
    body_groups_x: u32,
    body_groups_y: u32,
    _pad1: u32,
    _pad2: u32,
}
