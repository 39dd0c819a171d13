// Structs of the sleep kernels shared with the host. Each has a #[repr(C)] twin of the same
// name in crates/tumble-gpu/src/sleep/layout.rs, compared field by field with naga's layouter
// in tests/tests/gpu_layout.rs. As in layout.wgsl: no vec3, padding spelled out.

// The sleep stage's per-world settings. 16 bytes.
struct SleepParams {
    // Bodies in the world.
    body_count: u32,
    // Time step (s): what a resting body's rest time grows by per step.
    dt: f32,
    // Kinematic bodies (entries of the kinematic list).
    kinematic_count: u32,
    _pad: u32,
}
