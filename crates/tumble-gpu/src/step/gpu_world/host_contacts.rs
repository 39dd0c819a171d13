//! [`GpuWorld::step_with_contacts`]: the solver stages on manifolds made by the host, and
//! where each step's manifolds live.

use tumble_solver::{Body, Contact};

use super::*;
use crate::buffer_pool::bytes_of;
use crate::solver::WarmStartSweep;

impl GpuWorld {
    /// One step of the solver stages on manifolds made by the host (the CPU narrow phase):
    /// `contacts` with their warm-start impulses (tilt included), and for each the index of
    /// its pair's manifold in the previous call's list (or `NO_PREVIOUS`), which seeds its
    /// color. `bodies` holds the poses the manifolds were made from. The GPU collision stages
    /// do not run. The solved impulses come back with a contact readback.
    pub fn step_with_contacts(
        &mut self,
        contacts: &[Contact],
        previous: &[u32],
        bodies: &[Body],
    ) -> Result<(), GpuError> {
        if bodies.len() != self.bodies.len() {
            return Err(invalid(
                "bodies.len()",
                format!("{} for {} uploaded bodies", bodies.len(), self.bodies.len()),
            ));
        }
        if previous.len() != contacts.len() {
            return Err(invalid(
                "previous.len()",
                format!("{} for {} contacts", previous.len(), contacts.len()),
            ));
        }
        let n = self.bodies.len() as u32;
        if let Some((k, c)) = contacts
            .iter()
            .enumerate()
            .find(|(_, c)| c.body_a >= n || c.body_b >= n || c.body_a == c.body_b)
        {
            return Err(invalid(
                format!("contacts[{k}] bodies"),
                (c.body_a, c.body_b),
            ));
        }
        if self.bodies.is_empty() {
            self.steps += 1;
            return Ok(());
        }
        // Host manifolds are a change: the steps after are not idle repeats.
        self.idle.changed();
        let count = contacts.len() as u32;
        let max_previous = previous
            .iter()
            .filter(|&&p| p != crate::constants::NO_PREVIOUS)
            .map(|&p| p + 1)
            .max()
            .unwrap_or(0);
        let capacity = count.max(max_previous).max(1);
        // The carried tilt impulses go where the manifolds' `previous` points, with the normal
        // in A's frame at the manifold's pose, so the GPU's normal check accepts them.
        let tilts: Vec<(u32, GpuTilt)> = contacts
            .iter()
            .zip(previous)
            .filter(|&(_, &p)| p != crate::constants::NO_PREVIOUS)
            .map(|(c, &p)| (p, gpu_tilt(c, &bodies[c.body_a as usize].pose)))
            .collect();
        self.solver.write_previous_tilts(n, capacity, &tilts)?;
        let mut manifolds = Vec::with_capacity(contacts.len());
        let mut points = Vec::with_capacity(contacts.len() * MAX_MANIFOLD_POINTS as usize);
        for (c, &p) in contacts.iter().zip(previous) {
            let (m, pts) = gpu_manifold(c, p);
            manifolds.push(m);
            points.extend_from_slice(&pts);
        }
        let cap = u64::from(capacity);
        let sizes = [
            (HOST_MANIFOLDS, bytes_of::<GpuManifold>(cap)),
            (
                HOST_POINTS,
                bytes_of::<GpuContact>(cap * u64::from(MAX_MANIFOLD_POINTS)),
            ),
            (HOST_WORK, bytes_of::<WorkList>(1)),
        ];
        self.pool.ensure_all(&sizes, STORAGE_USAGE)?;
        let queue = &self.ctx.queue;
        queue.write_buffer(
            self.pool.get(HOST_MANIFOLDS),
            0,
            bytemuck::cast_slice(&manifolds),
        );
        queue.write_buffer(self.pool.get(HOST_POINTS), 0, bytemuck::cast_slice(&points));
        queue.write_buffer(
            self.pool.get(HOST_WORK),
            0,
            bytemuck::bytes_of(&WorkList::for_count(count)),
        );
        self.take_stats()?;
        let path = match self.config.path {
            PathPolicy::Always(path) => path,
            PathPolicy::Auto => SolvePath::choose(n, count),
        };
        let params = self.params();
        let mut encoder = self.ctx.encoder("tumble solver step");
        self.timer.reset();
        // Host wakes still apply; islands only fall asleep in `step`.
        self.record_wakes_and_impulses(&mut encoder);
        let inputs = SolverInputs {
            buffers: StepBuffers {
                manifolds: self.pool.get(HOST_MANIFOLDS),
                contacts: self.pool.get(HOST_POINTS),
                contact_work: self.pool.get(HOST_WORK),
                ..self.collision.buffers(self.pool.get(BODIES))
            },
            body_count: n,
            contact_capacity: capacity,
        };
        // Host manifolds may pair two bodies neither of which is dynamic on the device (fixed,
        // kinematic, or asleep there), which the broad phase never pairs. The per-body warm
        // start visits a constraint only from its dynamic bodies, so it would leave such a
        // constraint's running normal-impulse total out (no velocity changes either way); the
        // colored sweep visits every constraint, so host steps take it.
        let sweep = self.solver.warm_start_sweep();
        self.solver.set_warm_start_sweep(WarmStartSweep::ByColor);
        let recorded =
            self.solver
                .record(&mut encoder, &mut self.timer, &inputs, &params.params, path);
        self.solver.set_warm_start_sweep(sweep);
        recorded?;
        self.source = ContactSource::Host;
        if let Some(events) = &mut self.events {
            events.forget();
        }
        self.host_count = count;
        self.finish_step(encoder, path, true)
    }

    /// The buffers holding the last step's manifolds, points and work list (handles are
    /// shared, so these are cheap clones), and the manifold capacity.
    pub(super) fn contact_buffers(&self) -> (wgpu::Buffer, wgpu::Buffer, wgpu::Buffer, u32) {
        match self.source {
            ContactSource::Collision => {
                let b = self.collision.buffers(self.pool.get(BODIES));
                (
                    b.manifolds.clone(),
                    b.contacts.clone(),
                    b.contact_work.clone(),
                    self.collision.pair_capacity(),
                )
            }
            ContactSource::Host => (
                self.pool.get(HOST_MANIFOLDS).clone(),
                self.pool.get(HOST_POINTS).clone(),
                self.pool.get(HOST_WORK).clone(),
                self.host_count.max(1),
            ),
        }
    }
}
