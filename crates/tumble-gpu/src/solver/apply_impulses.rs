//! `apply_impulses`: impulses the host queued between steps, applied on the GPU at the start
//! of the next step (so applying one needs no readback). The CPU twin is the facade's
//! `World::apply_impulse` arithmetic, [`apply_impulse_cpu`].

use tumble_geometry::{Point3, Vec3};
use tumble_solver::{Body, BodyState};

use crate::kernel::kernel;

kernel! {
    /// Buffers of [`APPLY_IMPULSES`].
    pub struct ApplyImpulsesArgs {
        /// `array<GpuImpulse>`, exactly the queued ones.
        impulses,
        /// `array<GpuBody>`.
        bodies,
        /// `array<GpuPose>`.
        poses,
        /// `array<GpuVelocity>`, updated.
        velocities,
    }
    /// Kernel: a single thread, impulses in queue order.
    pub static APPLY_IMPULSES = "solver/apply_impulses.wgsl";
}

/// The CPU twin: `impulse` at world `point` on a dynamic body changes its velocities by
/// `M^-1 j` and `I^-1 (r x j)`; other bodies are unaffected.
pub fn apply_impulse_cpu(body: &Body, state: &mut BodyState, impulse: &Vec3, point: &Point3) {
    if !body.is_dynamic() {
        return;
    }
    let r = point.coords - body.pose.translation.vector;
    state.linear_velocity += body.inverse_mass_axes().component_mul(impulse);
    state.angular_velocity += body.inverse_inertia_world() * r.cross(impulse);
}
