//! Host twins of the structs in `shaders/common/solver_types.wgsl`: `#[repr(C)]`, `Pod`,
//! explicit padding, the same names and field names as in WGSL. The solver test compares each
//! with naga's layouter through [`solver_struct_layouts`]. Manifolds and contact points are
//! the collision stages' `GpuManifold` and `GpuContact` ([`crate::layout`]).

use bytemuck::{Pod, Zeroable};
use tumble_geometry::MAX_MANIFOLD_POINTS;

use crate::layout::host_structs;

host_structs! {
    /// Every struct of `solver_types.wgsl`, for the layout check against naga.
    pub fn solver_struct_layouts();

    /// A body's constant solver data. 96 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuBody {
            /// Local principal inverse moments (zero for fixed and kinematic); `w`: inverse mass.
            pub inverse_inertia: [f32; 4],
            /// Local principal moments, zero where the inverse is zero; `w` unused.
            pub inertia: [f32; 4],
            /// `BODY_FIXED`, `BODY_DYNAMIC` or `BODY_KINEMATIC`.
            pub kind: u32,
            /// Translation lock bits `0..3`, rotation lock bits `LOCK_ROTATION_SHIFT..+3`.
            pub locks: u32,
            /// Coulomb friction coefficient.
            pub friction: f32,
            /// Coefficient of restitution.
            pub restitution: f32,
            /// Linear damping rate, 1/s.
            pub linear_damping: f32,
            /// Angular damping rate, 1/s.
            pub angular_damping: f32,
            /// The independent world the body belongs to (0 in a world stepped alone): the
            /// coloring numbers a world's constraints from its first (`world_starts.wgsl`).
            pub world: u32,
            pad _pad1: u32,
            /// Persistent force at the centre of mass (N, world); `w`: gravity scale.
            pub force: [f32; 4],
            /// Persistent torque (N m, world); `w` unused.
            pub torque: [f32; 4],
    }

    /// A body's per-step solver state. 96 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuSolverBody {
            /// Translation since the start of the step; `w` unused.
            pub delta_position: [f32; 4],
            /// Rotation since the start of the step, `(x, y, z, w)`.
            pub delta_rotation: [f32; 4],
            /// Inverse mass per world axis (zero on locked axes); `w` unused.
            pub inverse_mass: [f32; 4],
            /// First column of the world inverse inertia; `w` unused.
            pub inverse_inertia_x: [f32; 4],
            /// Second column.
            pub inverse_inertia_y: [f32; 4],
            /// Third column.
            pub inverse_inertia_z: [f32; 4],
    }

    /// One point of a prepared constraint. 64 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuConstraintPoint {
            /// Anchor on A (world axes); `w`: base separation.
            pub anchor_a: [f32; 4],
            /// Anchor on B; `w`: normal effective mass.
            pub anchor_b: [f32; 4],
            /// Effective mass of the first friction row.
            pub tangent_mass_1: f32,
            /// Effective mass of the second friction row.
            pub tangent_mass_2: f32,
            /// Accumulated normal impulse of the current substep.
            pub normal_impulse: f32,
            /// Normal impulse over the whole step.
            pub total_normal_impulse: f32,
            /// Accumulated impulse along `tangent1`.
            pub tangent_impulse_1: f32,
            /// Accumulated impulse along `tangent2`.
            pub tangent_impulse_2: f32,
            /// Normal relative velocity at preparation.
            pub relative_velocity: f32,
            pad _pad: f32,
    }

    /// The constraint of one manifold. 368 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuConstraint {
            /// Body A's index.
            pub body_a: u32,
            /// Body B's index.
            pub body_b: u32,
            /// Valid points.
            pub point_count: u32,
            /// `CONSTRAINT_DYNAMIC_A | CONSTRAINT_DYNAMIC_B`.
            pub flags: u32,
            /// Normal; `w`: combined friction.
            pub normal: [f32; 4],
            /// First tangent; `w`: combined restitution.
            pub tangent1: [f32; 4],
            /// Second tangent; `w`: Baumgarte slop.
            pub tangent2: [f32; 4],
            /// `bias_rate`, `mass_scale`, `impulse_scale`; `w` unused.
            pub softness: [f32; 4],
            /// Effective mass of the tilt row about `tangent1`.
            pub tilt_mass_1: f32,
            /// Effective mass of the tilt row about `tangent2`.
            pub tilt_mass_2: f32,
            /// Accumulated angular impulse about `tangent1`, N m s.
            pub tilt_impulse_1: f32,
            /// Accumulated angular impulse about `tangent2`, N m s.
            pub tilt_impulse_2: f32,
            /// Radius of the disc inscribed in the contact patch, m (0 below three points).
            pub patch_radius: f32,
            pad _pad0, _pad1, _pad2: f32,
            /// The points.
            pub points: [GpuConstraintPoint; MAX_MANIFOLD_POINTS],
    }

    /// A manifold's tilt impulse kept for the next step. 32 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuTilt {
            /// Tilt impulse as a world vector, N m s; `w` unused.
            pub impulse: [f32; 4],
            /// The manifold normal in body A's frame at the start of the step; `w` unused.
            pub local_normal: [f32; 4],
    }

    /// Step-wide solver values. 96 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct SolverParams {
            /// Gravity, m/s²; `w` unused.
            pub gravity: [f32; 4],
            /// Softness between two dynamic bodies: `bias_rate`, `mass_scale`, `impulse_scale`.
            pub contact_softness: [f32; 4],
            /// Softness against a fixed or kinematic body.
            pub static_softness: [f32; 4],
            /// Substep length, s.
            pub h: f32,
            /// `1 / h`.
            pub inv_h: f32,
            /// Push-out speed cap, m/s.
            pub max_push_out: f32,
            /// Restitution threshold speed, m/s.
            pub restitution_threshold: f32,
            /// Baumgarte slop, m (0 for the soft step).
            pub slop: f32,
            /// 1 to warm start, 0 not to.
            pub warm_start_scale: f32,
            /// Bodies in the step.
            pub body_count: u32,
            /// Substeps per step.
            pub substeps: u32,
            /// Biased passes per substep.
            pub iterations: u32,
            /// Relax passes per substep.
            pub relax_iterations: u32,
            /// 1 when the restitution pass runs.
            pub restitution: u32,
            /// 1 when the biased passes leave the friction rows to the relax passes
            /// (`FrictionPasses::RelaxOnly`), 0 when every pass solves them.
            pub relax_only_friction: u32,
    }

    /// Which color a per-color pass visits. 16 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct ColorPass {
            /// The color (`OVERFLOW_COLOR` for the overflow set).
            pub color: u32,
            /// 1 for a pass's tail: every constraint from `color` on, in one thread.
            pub tail: u32,
            pad _pad1, _pad2: u32,
    }

    /// A constraint's coloring state. 8 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct ColorSlot {
            /// Final color, `OVERFLOW_COLOR`, or `NO_COLOR`.
            pub color: u32,
            /// This round's proposal, or `NO_COLOR`.
            pub proposal: u32,
    }

    /// An impulse queued by the host for the next step. 48 bytes.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct GpuImpulse {
            /// The body.
            pub body: u32,
            pad _pad0, _pad1, _pad2: u32,
            /// Impulse, N s (world); `w` unused.
            pub impulse: [f32; 4],
            /// World point it acts at; `w` unused.
            pub point: [f32; 4],
    }
}
