//! [`GpuWorld`]'s bodies: the upload, edits of single bodies between steps (pose, velocity,
//! wake), and the impulses queued for the start of the next step.

use super::*;
use crate::kernels::remap_pairs::REMAP_DROPPED;
use crate::layout::{BODY_WORLD_SHIFT, GpuCollisionGroups, MAX_WORLDS};

impl GpuWorld {
    /// Wakes body `i`'s island by the start of the next step (and restarts its rest time);
    /// a no-op for an awake body or with sleep off. Setting a pose or a velocity or applying
    /// an impulse does the same.
    pub fn wake_up(&mut self, i: usize) -> Result<(), GpuError> {
        self.check_body(i)?;
        self.idle.changed();
        self.sleep.queue_wake(i as u32);
        Ok(())
    }

    /// Uploads every body (cold data, pose, velocities); body `i` is `bodies[i]` from now on.
    /// Warm starting and color seeds start over (indices may have been reassigned), and the
    /// pipelines are specialized for the effects these bodies use.
    pub fn set_bodies(&mut self, bodies: &[Body], states: &[BodyState]) -> Result<(), GpuError> {
        self.set_bodies_in_worlds(bodies, states, &[])
    }

    /// [`Self::set_bodies`] for bodies of several independent worlds: body `i` belongs to
    /// world `worlds[i]` (empty: every body to world 0). Worlds are numbered from 0 without
    /// gaps and each world's bodies are one run (`worlds` never decreases and grows by at
    /// most 1). Bodies of different worlds never pair, and each world's bodies move exactly
    /// as they do when that world's bodies alone are given to a `GpuWorld` of the same
    /// config: the broad phase sorts by world first, the coloring numbers each world's
    /// constraints from its first, and every other kernel works per body or per pair.
    /// Errs, changing nothing, on a bad `worlds`.
    pub fn set_bodies_in_worlds(
        &mut self,
        bodies: &[Body],
        states: &[BodyState],
        worlds: &[u32],
    ) -> Result<(), GpuError> {
        self.upload(bodies, states, worlds, None).map(|_| ())
    }

    /// [`Self::set_bodies_in_worlds`] that keeps the contact history of the worlds whose
    /// bodies did not change: `remap[i]`, for body `i` of the last upload, is its index in
    /// this one, or `REMAP_DROPPED` (`crate::kernels::remap_pairs`) with the index at which
    /// its world's pairs are dropped (the new index of that world's first body, or of the
    /// next world's when it has none). A kept world's bodies must keep their order and
    /// world order must be kept. Those worlds then step as if nothing had been uploaded,
    /// the others as if uploaded fresh, so each world of a batch keeps the bits of the same
    /// world run alone while worlds and bodies come and go around it (sleep restarts,
    /// though: every body wakes with its rest time at zero). True when the pairs were kept;
    /// false when the pair buffers had to grow and every world restarts.
    pub fn set_bodies_in_worlds_keeping(
        &mut self,
        bodies: &[Body],
        states: &[BodyState],
        worlds: &[u32],
        remap: &[u32],
    ) -> Result<bool, GpuError> {
        if remap.len() != self.bodies.len() {
            return Err(invalid(
                "remap.len()",
                format!("{} for {} bodies uploaded", remap.len(), self.bodies.len()),
            ));
        }
        if let Some((i, r)) = remap.iter().enumerate().find(|&(_, &r)| {
            r & !REMAP_DROPPED > bodies.len() as u32
                || (r & REMAP_DROPPED == 0 && r >= bodies.len() as u32)
        }) {
            return Err(invalid(
                format!("remap[{i}]"),
                format!("{r:#x} for {} bodies", bodies.len()),
            ));
        }
        self.upload(bodies, states, worlds, Some(remap))
    }

    fn upload(
        &mut self,
        bodies: &[Body],
        states: &[BodyState],
        worlds: &[u32],
        remap: Option<&[u32]>,
    ) -> Result<bool, GpuError> {
        if states.len() != bodies.len() {
            return Err(invalid(
                "states.len()",
                format!("{} for {} bodies", states.len(), bodies.len()),
            ));
        }
        let world_count = check_worlds(worlds, bodies.len())?;
        self.stats.reset()?;
        self.idle.changed();
        self.pending.clear();
        self.impulses.clear();
        self.known_manifolds = None;
        let world_of = |i: usize| worlds.get(i).copied().unwrap_or(0);
        let mut kept = false;
        let gpu: Vec<GpuBody> = bodies
            .iter()
            .enumerate()
            .map(|(i, b)| GpuBody {
                world: world_of(i),
                ..gpu_body(b)
            })
            .collect();
        if !bodies.is_empty() {
            let poses: Vec<GpuPose> = bodies.iter().map(|b| GpuPose::from_pose(&b.pose)).collect();
            let velocities: Vec<GpuVelocity> = states.iter().map(gpu_velocity).collect();
            let shapes: Vec<_> = bodies
                .iter()
                .enumerate()
                .map(|(i, b)| {
                    let mut shape = gpu_shape(b);
                    shape.flags |= world_of(i) << BODY_WORLD_SHIFT;
                    shape
                })
                .collect();
            kept = match remap {
                Some(remap) if !self.bodies.is_empty() => {
                    self.collision
                        .set_bodies_remapped(&poses, &velocities, &shapes, remap)?
                }
                _ => {
                    self.collision.set_bodies(&poses, &velocities, &shapes)?;
                    false
                }
            };
            let groups: Vec<GpuCollisionGroups> = bodies
                .iter()
                .map(|b| GpuCollisionGroups::of(b.groups))
                .collect();
            self.collision.set_groups(0, &groups)?;
            if !kept {
                self.collision.forget_history();
            }
            let bytes: &[u8] = bytemuck::cast_slice(&gpu);
            self.pool
                .ensure(BODIES, bytes.len() as u64, STORAGE_USAGE)?;
            self.ctx.queue.write_buffer(self.pool.get(BODIES), 0, bytes);
        }
        self.solver
            .set_effects(Effects::of_bodies(bodies, &self.config.gravity))?;
        if !kept {
            self.solver.forget_colors();
        }
        let firsts: Vec<u32> = (0..world_count)
            .map(|w| worlds.partition_point(|&x| x < w) as u32)
            .collect();
        self.max_world_bodies = (0..world_count as usize)
            .map(|w| {
                let end = firsts.get(w + 1).copied().unwrap_or(bodies.len() as u32);
                end - firsts[w]
            })
            .max()
            .unwrap_or(0);
        self.solver.set_worlds(&firsts, bodies.len() as u32);
        self.sleep.reset(&gpu, self.config.dt)?;
        self.bodies = bodies.to_vec();
        self.worlds = worlds.to_vec();
        Ok(kept)
    }

    /// Makes the next step meet the worlds `worlds` (indices of
    /// [`Self::set_bodies_in_worlds`]) as if for the first time: their pairs of the last step
    /// are dropped, so no manifold, impulse or color seed is carried over for them, while the
    /// other worlds keep theirs. With the poses and velocities of those worlds' bodies set
    /// again (and sleep off), such a world then steps with the bits of the same world uploaded
    /// fresh. Errs, changing nothing, on a world index out of range.
    pub fn forget_worlds(&mut self, worlds: &[u32]) -> Result<(), GpuError> {
        let count = self.world_count();
        if let Some(&w) = worlds.iter().find(|&&w| w >= count) {
            return Err(invalid(
                "worlds",
                format!("{w} (the step holds {count} worlds)"),
            ));
        }
        if worlds.is_empty() {
            return Ok(());
        }
        // Each world's first body plus one, for the worlds to forget.
        let mut forget = vec![0u32; count as usize];
        for &w in worlds {
            let first = if self.worlds.is_empty() {
                0
            } else {
                self.worlds.partition_point(|&x| x < w)
            };
            forget[w as usize] = first as u32 + 1;
        }
        self.idle.changed();
        self.collision.forget_worlds(&forget)
    }

    /// Independent worlds the bodies form ([`Self::set_bodies_in_worlds`]); 1 after
    /// [`Self::set_bodies`].
    pub fn world_count(&self) -> u32 {
        self.solver.world_count()
    }

    /// Sets body `i`'s properties that may change after the upload, from `body`: its
    /// collision groups, force, torque and gravity scale (every other field of `body` is
    /// ignored). Takes effect from the next step, and wakes the body's island. Errs, changing
    /// nothing, on a non-finite force, torque or gravity scale.
    pub fn set_body_properties(&mut self, i: usize, body: &Body) -> Result<(), GpuError> {
        self.check_body(i)?;
        require_finite("force", &body.force)?;
        require_finite("torque", &body.torque)?;
        if !body.gravity_scale.is_finite() {
            return Err(invalid("gravity_scale", body.gravity_scale));
        }
        let kept = &mut self.bodies[i];
        kept.groups = body.groups;
        kept.force = body.force;
        kept.torque = body.torque;
        kept.gravity_scale = body.gravity_scale;
        let record = GpuBody {
            world: self.worlds.get(i).copied().unwrap_or(0),
            ..gpu_body(kept)
        };
        self.collision
            .set_groups(i, &[GpuCollisionGroups::of(body.groups)])?;
        self.sleep.update_awake_body(i as u32, &record);
        self.write_body(i, |b| b.bodies, &record)
    }

    pub(super) fn check_body(&self, i: usize) -> Result<(), GpuError> {
        if i >= self.bodies.len() {
            return Err(invalid(
                "body",
                format!("{i} (the world has {} bodies)", self.bodies.len()),
            ));
        }
        Ok(())
    }

    /// Writes body `i`'s record in one of the per-body arrays of the step's buffers, after
    /// the impulses queued before it, and wakes its island.
    fn write_body<T: bytemuck::Pod>(
        &mut self,
        i: usize,
        array: for<'a> fn(&StepBuffers<'a>) -> &'a wgpu::Buffer,
        record: &T,
    ) -> Result<(), GpuError> {
        self.flush_impulses()?;
        self.idle.changed();
        self.sleep.queue_wake(i as u32);
        let offset = (i * std::mem::size_of::<T>()) as u64;
        let buffer = array(&self.collision.buffers(self.pool.get(BODIES)));
        self.ctx
            .queue
            .write_buffer(buffer, offset, bytemuck::bytes_of(record));
        Ok(())
    }

    /// Teleports body `i` (velocities kept). Takes effect before the next step.
    pub fn set_pose(&mut self, i: usize, pose: &Pose) -> Result<(), GpuError> {
        self.check_body(i)?;
        let finite = pose.translation.vector.iter().all(|c| c.is_finite())
            && pose.rotation.coords.iter().all(|c| c.is_finite());
        if !finite {
            return Err(invalid("pose", pose));
        }
        self.write_body(i, |b| b.poses, &GpuPose::from_pose(pose))
    }

    /// Sets body `i`'s linear and angular velocity. Takes effect before the next step.
    pub fn set_velocity(
        &mut self,
        i: usize,
        linear: &Vec3,
        angular: &Vec3,
    ) -> Result<(), GpuError> {
        self.check_body(i)?;
        require_finite("linear_velocity", linear)?;
        require_finite("angular_velocity", angular)?;
        let velocity = gpu_velocity(&BodyState::moving(*linear, *angular));
        self.write_body(i, |b| b.velocities, &velocity)
    }

    /// Queues an impulse (N s, world) at a world point on body `i`, applied on the GPU at
    /// the start of the next step, in queue order (fixed and kinematic bodies ignore it).
    pub fn apply_impulse(
        &mut self,
        i: usize,
        impulse: &Vec3,
        point: &Point3,
    ) -> Result<(), GpuError> {
        self.check_body(i)?;
        require_finite("impulse", impulse)?;
        require_finite("point", &point.coords)?;
        self.idle.changed();
        self.sleep.queue_wake(i as u32);
        self.impulses.push(GpuImpulse {
            body: i as u32,
            impulse: [impulse.x, impulse.y, impulse.z, 0.0],
            point: [point.x, point.y, point.z, 0.0],
            ..Default::default()
        });
        Ok(())
    }

    /// Records the wakes of the islands queued to wake, then the queued impulses: an impulse
    /// skips a body that is not dynamic, and a sleeping body is fixed to the kernels.
    pub(super) fn record_wakes_and_impulses(&mut self, encoder: &mut wgpu::CommandEncoder) {
        let bodies = self.pool.get(BODIES);
        let shapes = self.collision.buffers(bodies).shapes;
        self.sleep
            .record_wake(encoder, &mut self.timer, bodies, shapes);
        self.record_impulses(encoder);
    }

    /// Records the queued impulses (if any) and empties the queue.
    pub(super) fn record_impulses(&mut self, encoder: &mut wgpu::CommandEncoder) {
        if self.impulses.is_empty() {
            return;
        }
        let queued = self.ctx.storage_buffer("queued impulses", &self.impulses);
        let kernel = &self.solver.pipelines().apply_impulses;
        let buffers = self.collision.buffers(self.pool.get(BODIES));
        let group = kernel.bind_named(&self.ctx, |name| match name {
            "impulses" => &queued,
            "bodies" => self.pool.get(BODIES),
            "poses" => buffers.poses,
            "velocities" => buffers.velocities,
            _ => unreachable!("no apply_impulses binding {name}"),
        });
        let mut pass = self.timer.begin_pass(encoder, "apply_impulses");
        kernel.dispatch_workgroups(&mut pass, &group, 1, 1);
        drop(pass);
        self.impulses.clear();
    }

    /// Submits the queued impulses now, so a later write of a pose or velocity lands after
    /// them, as the calls were made. The islands queued to wake wake first, as at the start
    /// of a step: an impulse skips a sleeping body (a fixed one to the kernel).
    pub(super) fn flush_impulses(&mut self) -> Result<(), GpuError> {
        if self.impulses.is_empty() {
            return Ok(());
        }
        let mut encoder = self.ctx.encoder("impulses");
        self.timer.reset();
        self.record_wakes_and_impulses(&mut encoder);
        self.ctx.submit(encoder)?;
        Ok(())
    }
}

/// An `Err` naming `field` unless every component of `v` is finite.
fn require_finite(field: &str, v: &Vec3) -> Result<(), GpuError> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(invalid(field, v))
    }
}

/// The number of worlds `worlds` numbers for `bodies` bodies (1 when empty); errs, naming the
/// entry, unless it has one entry per body, starts at 0 and each entry equals the one before
/// or is one more.
fn check_worlds(worlds: &[u32], bodies: usize) -> Result<u32, GpuError> {
    if worlds.is_empty() {
        return Ok(1);
    }
    if worlds.len() != bodies {
        return Err(invalid(
            "worlds.len()",
            format!("{} for {bodies} bodies", worlds.len()),
        ));
    }
    let mut last = 0;
    for (i, &w) in worlds.iter().enumerate() {
        let expected = if i == 0 {
            w == 0
        } else {
            w == last || w == last + 1
        };
        if !expected {
            let want = if i == 0 {
                "0".to_string()
            } else {
                format!("{last} or {}", last + 1)
            };
            return Err(invalid(
                format!("worlds[{i}]"),
                format!("{w} (expected {want}: worlds are numbered from 0, each one run)"),
            ));
        }
        last = w;
    }
    if last >= MAX_WORLDS {
        return Err(GpuError::LimitExceeded {
            what: "worlds".into(),
            value: u64::from(last) + 1,
            limit_name: "tumble_gpu::layout::MAX_WORLDS",
            limit: MAX_WORLDS.into(),
        });
    }
    Ok(last + 1)
}
