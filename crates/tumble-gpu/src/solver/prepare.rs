//! The preparation kernels: `prepare_bodies` (deltas reset, masses in world axes) and
//! `prepare_contacts` (one constraint per manifold), with their CPU twins built on
//! tumble-solver's own functions.

use tumble_solver::{Body, BodyState, Contact, Mat3, prepare_contact};

use crate::kernel::KernelSpec;
use crate::shader::file;

use super::convert::gpu_constraint;
use super::layout::{GpuConstraint, GpuSolverBody};
use super::params::StepParams;

/// Kernel: one thread per body.
pub static PREPARE_BODIES: KernelSpec = KernelSpec::new(file("solver/prepare_bodies.wgsl"));

/// Kernel: one thread per constraint slot.
pub static PREPARE_CONTACTS: KernelSpec = KernelSpec::new(file("solver/prepare_contacts.wgsl"));

/// Kernel: one thread per body, the warm-start pass of the graph colors (the per-body
/// lists `prepare_contacts` writes into the coloring's marks).
pub static WARM_START_BODIES: KernelSpec = KernelSpec::new(file("solver/warm_start_bodies.wgsl"));

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
