//! The hybrid mix (the thesis's fastest): collision on the GPU, solver on the CPU. Each step
//! uploads the bodies' motion, runs the GPU collision stages, reads the manifolds back as
//! the CPU's contacts (with the impulses the GPU matching carried over), and after the CPU
//! solve writes the solved impulses back, so the next step's GPU matching warm starts them.
//! The patch tilt impulses, which the collision stages do not carry, are kept here by pair
//! slot and handed over through each manifold's `previous` index, with the CPU cache's normal
//! check.

use tumble_geometry::Vec3;
use tumble_solver::{Body, BodyState, Contact, PERSIST_NORMAL_COS};

use crate::collision::{CollisionConfig, CollisionSnapshot, GpuCollision, ReadbackRequest};
use crate::constants::NO_PREVIOUS;
use crate::layout::{GpuCollisionGroups, GpuContact, GpuPose};
use crate::solver::convert::{gpu_shape, gpu_velocity};
use crate::{GpuContext, GpuError, MAX_MANIFOLD_POINTS, StageTimer};

/// Pair slots added on overflow: a quarter on top of what the step asked for, so a pile that
/// is still getting denser does not overflow again at once.
const GROWTH_DIVISOR: u32 = 4;

/// GPU collision for a CPU solver.
#[derive(Debug)]
pub struct HybridCollision {
    ctx: GpuContext,
    collision: GpuCollision,
    /// Whether the uploaded shapes match the bodies (false after [`Self::invalidate`]).
    shapes_uploaded: bool,
    /// The collision groups uploaded, per body.
    groups: Vec<GpuCollisionGroups>,
    /// Last step's points, as read back, to write the solved impulses into.
    last_points: Vec<GpuContact>,
    /// This step's manifold normal in body A's frame, per pair slot (when it has points).
    local_normals: Vec<Option<Vec3>>,
    /// Last step's tilt impulse and normal in A's frame, per pair slot.
    last_tilts: Vec<Option<(Vec3, Vec3)>>,
    /// Last step's candidate pairs, as read back.
    last_pairs: Vec<(u32, u32)>,
}

impl HybridCollision {
    /// The collision stages on `ctx` with `config`. A step whose pairs overflow the buffers is
    /// run again with larger ones before anything is returned.
    pub fn new(ctx: &GpuContext, config: CollisionConfig) -> Result<Self, GpuError> {
        Ok(Self {
            ctx: ctx.clone(),
            collision: GpuCollision::new(ctx, config)?,
            shapes_uploaded: false,
            groups: Vec::new(),
            last_points: Vec::new(),
            local_normals: Vec::new(),
            last_tilts: Vec::new(),
            last_pairs: Vec::new(),
        })
    }

    /// Bytes of the collision stages' device buffers.
    pub fn buffer_bytes(&self) -> u64 {
        self.collision.buffer_bytes()
    }

    /// Forgets the uploaded bodies: the next [`Self::collide`] uploads shapes again and
    /// starts without matching history (after bodies were added, removed or reordered).
    pub fn invalidate(&mut self) {
        self.shapes_uploaded = false;
        self.last_tilts.clear();
    }

    /// Runs the GPU collision stages on the bodies' current poses and velocities and returns
    /// each manifold with points as `(pair slot, contact)`: bodies in index order (A < B),
    /// warm-start impulses carried over from the last step by feature id, or by position in
    /// body A's frame where ids changed (the CPU contact cache's rule).
    pub fn collide(
        &mut self,
        bodies: &[Body],
        states: &[BodyState],
    ) -> Result<Vec<(u32, Contact)>, GpuError> {
        if bodies.is_empty() {
            self.last_points.clear();
            self.last_tilts.clear();
            self.last_pairs.clear();
            return Ok(Vec::new());
        }
        let poses: Vec<_> = bodies.iter().map(|b| GpuPose::from_pose(&b.pose)).collect();
        let velocities: Vec<_> = states.iter().map(gpu_velocity).collect();
        if self.shapes_uploaded && self.collision.body_count() as usize == bodies.len() {
            self.collision.set_motion(&poses, &velocities)?;
        } else {
            let shapes: Vec<_> = bodies.iter().map(gpu_shape).collect();
            self.collision.set_bodies(&poses, &velocities, &shapes)?;
            self.collision.forget_history();
            self.last_tilts.clear();
            self.shapes_uploaded = true;
            self.groups = vec![GpuCollisionGroups::ALL; bodies.len()];
        }
        // Groups change without a new upload (`World::set_collision_groups`): the few
        // bodies whose groups differ from the uploaded ones are written.
        for (i, b) in bodies.iter().enumerate() {
            let groups = GpuCollisionGroups::of(b.groups);
            if self.groups[i] != groups {
                self.collision.set_groups(i, &[groups])?;
                self.groups[i] = groups;
            }
        }
        let mut snapshot = self.run_once()?;
        if snapshot.check_overflow().is_err() {
            // More pairs than slots: grow (which drops the matching history) and run the
            // same collision stages again; the bodies have not moved.
            let requested = snapshot.work.requested;
            self.collision
                .reserve_pairs(requested.saturating_add(requested / GROWTH_DIVISOR))?;
            self.last_tilts.clear();
            snapshot = self.run_once()?;
            snapshot.check_overflow()?;
        }
        self.last_points = snapshot.contacts.clone();
        self.last_pairs = std::mem::take(&mut snapshot.pairs);
        let mut contacts = snapshot.solver_contacts();
        self.local_normals = vec![None; snapshot.manifolds.len()];
        for (slot, contact) in &mut contacts {
            let k = *slot as usize;
            let rotation = bodies[contact.body_a as usize].pose.rotation;
            let local = rotation.inverse_transform_vector(&contact.manifold.normal);
            self.local_normals[k] = Some(local);
            // As the CPU cache's warm_tilt: last step's tilt when the normal turned by less
            // than the angle of PERSIST_NORMAL_COS in A's frame.
            let previous = snapshot.manifolds[k].previous;
            if previous != NO_PREVIOUS
                && let Some(Some((tilt, old_normal))) = self.last_tilts.get(previous as usize)
                && local.dot(old_normal) >= PERSIST_NORMAL_COS
            {
                contact.tilt_impulse = *tilt;
            }
        }
        Ok(contacts)
    }

    /// The candidate pairs of the broad phase in the last [`Self::collide`], `(a, b)` with
    /// `a < b` in body index order, sorted: every pair slot, touching or not.
    pub fn pairs(&self) -> &[(u32, u32)] {
        &self.last_pairs
    }

    /// Records the collision stages and a readback of their manifolds, submits, and waits for
    /// the copy ([`GpuCollision::receive`] polls until the map callback has run).
    fn run_once(&mut self) -> Result<CollisionSnapshot, GpuError> {
        let mut encoder = self.ctx.encoder("hybrid collision");
        self.collision
            .record(&mut encoder, &mut StageTimer::disabled(&self.ctx))?;
        let plan = self
            .collision
            .record_readback(&mut encoder, ReadbackRequest::CONTACTS)?;
        self.ctx.submit(encoder)?;
        let pending = self.collision.submit_readback(plan);
        self.collision.receive(pending)
    }

    /// Writes the CPU solver's impulses of the last [`Self::collide`] back to the GPU, where
    /// the next step's matching carries them to the points with the same feature ids (or at
    /// the same place on body A), and keeps the tilt impulses for the next step.
    pub fn store_impulses(&mut self, solved: &[(u32, Contact)]) -> Result<(), GpuError> {
        if self.last_points.is_empty() {
            return Ok(());
        }
        let per = MAX_MANIFOLD_POINTS as usize;
        let pairs = self.last_points.len() / per;
        for (slot, contact) in solved {
            let k = *slot as usize;
            let points = self
                .last_points
                .get_mut(k * per..(k + 1) * per)
                .ok_or_else(|| GpuError::InvalidInput {
                    field: "solved pair slot".into(),
                    value: format!("{k} (last step had {pairs} pairs)"),
                })?;
            for (p, j) in points.iter_mut().zip(&contact.impulses) {
                p.normal_impulse = j.normal;
                p.friction_impulse = [j.friction.x, j.friction.y, j.friction.z, 0.0];
            }
        }
        self.last_tilts = vec![None; self.local_normals.len()];
        for (slot, contact) in solved {
            let k = *slot as usize;
            if let Some(Some(normal)) = self.local_normals.get(k) {
                self.last_tilts[k] = Some((contact.tilt_impulse, *normal));
            }
        }
        self.ctx.queue.write_buffer(
            self.collision.contacts(),
            0,
            bytemuck::cast_slice(&self.last_points),
        );
        Ok(())
    }
}

/// What a [`HybridCollision`] keeps between steps, saved to the host.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SavedHybrid {
    /// The collision stages.
    pub collision: super::SavedCollision,
    /// Whether the uploaded shapes match the bodies.
    pub shapes_uploaded: bool,
    /// The collision groups uploaded, per body (memberships, filter).
    pub groups: Vec<[u32; 2]>,
    /// Last step's tilt impulse and normal in A's frame, per pair slot.
    pub last_tilts: Vec<Option<([f32; 3], [f32; 3])>>,
}

impl HybridCollision {
    /// Everything the next [`Self::collide`] reads (blocking).
    pub fn save_state(&self) -> Result<SavedHybrid, GpuError> {
        self.ctx.wait_idle()?;
        Ok(SavedHybrid {
            collision: self.collision.save_state()?,
            shapes_uploaded: self.shapes_uploaded,
            groups: self
                .groups
                .iter()
                .map(|g| [g.memberships, g.filter_bits])
                .collect(),
            last_tilts: self
                .last_tilts
                .iter()
                .map(|t| t.map(|(tilt, normal)| (tilt.into(), normal.into())))
                .collect(),
        })
    }

    /// Takes the state [`Self::save_state`] gave (into a new one with the same settings).
    /// Errs when it does not fit, naming the part.
    pub fn load_state(&mut self, saved: &SavedHybrid) -> Result<(), GpuError> {
        self.collision.load_state(&saved.collision)?;
        self.shapes_uploaded = saved.shapes_uploaded;
        self.groups = saved
            .groups
            .iter()
            .map(|&[memberships, filter_bits]| GpuCollisionGroups {
                memberships,
                filter_bits,
            })
            .collect();
        self.last_tilts = saved
            .last_tilts
            .iter()
            .map(|t| t.map(|(tilt, normal)| (Vec3::from(tilt), Vec3::from(normal))))
            .collect();
        Ok(())
    }
}
