// requires: common/layout.wgsl
// Structs of the solver stages shared with the host. Each has a #[repr(C)] twin of the same
// name in crates/tumble-gpu/src/solver/layout.rs, compared field by field with naga's layouter
// in tests/tests/gpu_solver.rs. As in layout.wgsl: no vec3, padding spelled out. The solver
// reads the collision stages' GpuManifold and GpuContact (layout.wgsl) as they are.

// A body's constant solver data, uploaded with the body (and again when its force, torque or
// gravity scale changes). 96 bytes.
struct GpuBody {
    // Local principal inverse moments (1/(kg m^2)), zero for fixed and kinematic bodies;
    // w: inverse mass (1/kg).
    inverse_inertia: vec4<f32>,
    // Local principal moments (kg m^2), zero where the inverse is zero; w unused.
    inertia: vec4<f32>,
    // BODY_FIXED, BODY_DYNAMIC or BODY_KINEMATIC.
    kind: u32,
    // Bit k locks translation along world axis k; bit k + LOCK_ROTATION_SHIFT locks rotation.
    locks: u32,
    // Coulomb friction coefficient.
    friction: f32,
    // Coefficient of restitution.
    restitution: f32,
    // Damping rates (1/s).
    linear_damping: f32,
    angular_damping: f32,
    // The independent world the body belongs to (0 in a world stepped alone).
    world: u32,
    _pad1: u32,
    // Persistent force at the centre of mass (N, world), applied in every substep; w: the
    // multiple of gravity acting on the body.
    force: vec4<f32>,
    // Persistent torque (N m, world), applied in every substep; w unused.
    torque: vec4<f32>,
}

// A body's per-step solver state. 96 bytes.
struct GpuSolverBody {
    // Translation since the start of the step; w unused.
    delta_position: vec4<f32>,
    // Rotation since the start of the step, quaternion (x, y, z, w).
    delta_rotation: vec4<f32>,
    // Inverse mass per world axis, zero on locked axes; w unused.
    inverse_mass: vec4<f32>,
    // Columns of the world inverse inertia at the start of the step; w unused.
    inverse_inertia_x: vec4<f32>,
    inverse_inertia_y: vec4<f32>,
    inverse_inertia_z: vec4<f32>,
}

// One point of a prepared constraint. 64 bytes.
struct GpuConstraintPoint {
    // Contact point minus A's centre at the start of the step; w: base separation (m).
    anchor_a: vec4<f32>,
    // Contact point minus B's centre; w: effective mass of the normal row (kg).
    anchor_b: vec4<f32>,
    // Effective masses of the two friction rows.
    tangent_mass_1: f32,
    tangent_mass_2: f32,
    // Accumulated normal impulse of the current substep (>= 0).
    normal_impulse: f32,
    // Normal impulse applied over the whole step.
    total_normal_impulse: f32,
    // Accumulated friction impulses along tangent1 and tangent2.
    tangent_impulse_1: f32,
    tangent_impulse_2: f32,
    // Normal relative velocity at preparation (negative = approaching), for restitution.
    relative_velocity: f32,
    _pad: f32,
}

// The constraint of one manifold. 368 bytes.
struct GpuConstraint {
    body_a: u32,
    body_b: u32,
    point_count: u32,
    // CONSTRAINT_DYNAMIC_A | CONSTRAINT_DYNAMIC_B: which bodies the solver writes.
    flags: u32,
    // Unit normal from A to B; w: combined friction.
    normal: vec4<f32>,
    // First friction direction; w: combined restitution.
    tangent1: vec4<f32>,
    // Second friction direction (tangent1 x tangent2 = normal); w: Baumgarte slop (m).
    tangent2: vec4<f32>,
    // Position feedback: bias_rate (1/s), mass_scale, impulse_scale; w unused.
    softness: vec4<f32>,
    // Effective masses of the two tilt rows (relative rotation about tangent1, tangent2).
    tilt_mass_1: f32,
    tilt_mass_2: f32,
    // Accumulated angular impulses of the tilt rows (N m s).
    tilt_impulse_1: f32,
    tilt_impulse_2: f32,
    // Radius of the disc inscribed in the contact patch (m); 0 below three points.
    patch_radius: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
    points: array<GpuConstraintPoint, MAX_MANIFOLD_POINTS>,
}

// A manifold's tilt impulse kept for the next step. 32 bytes.
struct GpuTilt {
    // The patch's tilt impulse as a world vector (N m s); w unused.
    impulse: vec4<f32>,
    // The manifold normal in body A's frame at the start of the step; w unused.
    local_normal: vec4<f32>,
}

// Step-wide solver values, one uniform block. 96 bytes.
struct SolverParams {
    // Gravity (m/s^2); w unused.
    gravity: vec4<f32>,
    // Softness of contacts between two dynamic bodies: bias_rate, mass_scale, impulse_scale.
    contact_softness: vec4<f32>,
    // Softness of contacts with a fixed or kinematic body.
    static_softness: vec4<f32>,
    // Substep length (s) and its inverse.
    h: f32,
    inv_h: f32,
    // Largest separation speed the position feedback may ask for (m/s).
    max_push_out: f32,
    // Approach speed below which restitution is ignored (m/s).
    restitution_threshold: f32,
    // Baumgarte slop (m); 0 for the soft step.
    slop: f32,
    // 1 to warm start, 0 to start from zero impulses.
    warm_start_scale: f32,
    // Bodies in the step.
    body_count: u32,
    substeps: u32,
    // Biased and relax passes per substep.
    iterations: u32,
    relax_iterations: u32,
    // 1 when some material has restitution (the restitution pass runs).
    restitution: u32,
    // 1 when the biased passes leave the friction rows to the relax passes
    // (FrictionPasses::RelaxOnly), 0 when every pass solves them.
    relax_only_friction: u32,
}

// Which color a per-color pass visits. 16 bytes.
struct ColorPass {
    color: u32,
    // 1: the tail, every constraint from `color` on in one thread (solve_color_pass.wgsl).
    tail: u32,
    _pad1: u32,
    _pad2: u32,
}

// A constraint's coloring state. 8 bytes.
struct ColorSlot {
    // Final color, OVERFLOW_COLOR, or NO_COLOR while undecided.
    color: u32,
    // Color proposed in the current round, or NO_COLOR.
    proposal: u32,
}

// An impulse queued by the host, applied at the start of the next step. 48 bytes.
struct GpuImpulse {
    // The body.
    body: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    // Impulse (N s, world); w unused.
    impulse: vec4<f32>,
    // World point it acts at; w unused.
    point: vec4<f32>,
}
