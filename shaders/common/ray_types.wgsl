// Structs of the batched ray cast (cast_rays.wgsl), shared with the host: each has a
// #[repr(C)] twin of the same name in crates/tumble-gpu/src/kernels/cast_rays.rs, which the
// layout test compares with naga's layouter.

// One ray `origin + t dir`. 32 bytes.
struct GpuRay {
    // Start point (world); w unused.
    origin: vec4<f32>,
    // Direction, not zero, of any length (the time of impact is in its units); w unused.
    dir: vec4<f32>,
}

// The closest hit of one ray. 32 bytes.
struct GpuRayHit {
    // The body's outward unit normal at the hit, zero when the ray starts inside it; w unused.
    normal: vec4<f32>,
    // Time of impact, in units of the ray's direction.
    toi: f32,
    // Dense index of the body hit (meaningless when `hit` is 0).
    body: u32,
    // 1 when the ray hit a body, 0 when it hit nothing.
    hit: u32,
    _pad: u32,
}

// Parameters of cast_rays. 16 bytes.
struct RayCastParams {
    // Rays in the batch.
    rays: u32,
    // Bodies to test each ray against (dense indices 0..bodies of the pose and shape arrays).
    bodies: u32,
    // The largest time of impact a hit may have (infinity allowed).
    max_toi: f32,
    _pad: u32,
}
