//! The preparation kernels: `prepare_bodies` (deltas reset, masses in world axes) and
//! `prepare_contacts` (one constraint per manifold), with their CPU twins built on
//! tumble-solver's own functions.

use tumble_solver::{Body, BodyState, Contact, Mat3, prepare_contact};

use crate::kernel::{KernelArgs, KernelSpec};
use crate::shader::{Binding, ShaderSource, wgsl_file};

use super::convert::gpu_constraint;
use super::layout::{GpuConstraint, GpuSolverBody};
use super::params::StepParams;
use super::shaders::{BODY_COMMON, CONTACT_COMMON};

/// Kernel: one thread per body.
pub static PREPARE_BODIES: KernelSpec = KernelSpec {
    name: "prepare_bodies",
    source: ShaderSource {
        common: BODY_COMMON,
        kernel: wgsl_file!("solver/prepare_bodies.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// Kernel: one thread per manifold.
pub static PREPARE_CONTACTS: KernelSpec = KernelSpec {
    name: "prepare_contacts",
    source: ShaderSource {
        common: CONTACT_COMMON,
        kernel: wgsl_file!("solver/prepare_contacts.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`PREPARE_BODIES`].
pub struct PrepareBodiesArgs<'a> {
    /// `SolverParams`.
    pub params: &'a wgpu::Buffer,
    /// `array<GpuBody>`.
    pub bodies: &'a wgpu::Buffer,
    /// `array<GpuPose>`.
    pub poses: &'a wgpu::Buffer,
    /// Output `array<GpuSolverBody>`.
    pub solver_bodies: &'a wgpu::Buffer,
}

impl KernelArgs for PrepareBodiesArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![self.params, self.bodies, self.poses, self.solver_bodies]
    }
}

/// Buffers of [`PREPARE_CONTACTS`].
pub struct PrepareContactsArgs<'a> {
    /// `SolverParams`.
    pub params: &'a wgpu::Buffer,
    /// The contacts' `WorkList`.
    pub contact_work: &'a wgpu::Buffer,
    /// `array<GpuManifold>`.
    pub manifolds: &'a wgpu::Buffer,
    /// `array<GpuContact>`, `MAX_MANIFOLD_POINTS` per manifold, with carried impulses.
    pub contacts: &'a wgpu::Buffer,
    /// `array<GpuBody>`.
    pub bodies: &'a wgpu::Buffer,
    /// `array<GpuPose>`.
    pub poses: &'a wgpu::Buffer,
    /// `array<GpuVelocity>`.
    pub velocities: &'a wgpu::Buffer,
    /// `array<GpuSolverBody>` from `prepare_bodies`.
    pub solver_bodies: &'a wgpu::Buffer,
    /// Last step's `array<GpuTilt>`, indexed by the manifolds' `previous`.
    pub previous_tilts: &'a wgpu::Buffer,
    /// Output `array<GpuConstraint>`.
    pub constraints: &'a wgpu::Buffer,
}

impl KernelArgs for PrepareContactsArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.contact_work,
            self.manifolds,
            self.contacts,
            self.bodies,
            self.poses,
            self.velocities,
            self.solver_bodies,
            self.previous_tilts,
            self.constraints,
        ]
    }
}

/// A body's solver state at the start of a step, from its CPU form.
pub fn solver_body(body: &Body) -> GpuSolverBody {
    let m = body.inverse_mass_axes();
    let i: Mat3 = body.inverse_inertia_world();
    let column = |c: usize| [i[(0, c)], i[(1, c)], i[(2, c)], 0.0];
    GpuSolverBody {
        delta_position: [0.0; 4],
        delta_rotation: [0.0, 0.0, 0.0, 1.0],
        inverse_mass: [m.x, m.y, m.z, 0.0],
        inverse_inertia_x: column(0),
        inverse_inertia_y: column(1),
        inverse_inertia_z: column(2),
    }
}

/// The CPU twin of [`PREPARE_BODIES`].
pub fn prepare_bodies_cpu(bodies: &[Body]) -> Vec<GpuSolverBody> {
    bodies.iter().map(solver_body).collect()
}

/// The CPU twin of [`PREPARE_CONTACTS`]: tumble-solver's `prepare_contact` per manifold.
pub fn prepare_contacts_cpu(
    bodies: &[Body],
    states: &[BodyState],
    contacts: &[Contact],
    step: &StepParams,
) -> Vec<GpuConstraint> {
    let inverse_inertia: Vec<Mat3> = bodies.iter().map(Body::inverse_inertia_world).collect();
    (0..contacts.len())
        .map(|i| {
            gpu_constraint(&prepare_contact(
                bodies,
                &inverse_inertia,
                states,
                contacts,
                i,
                &step.prepare,
            ))
        })
        .collect()
}
