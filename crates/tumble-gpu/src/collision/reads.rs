//! [`GpuCollision`]'s reads: readback recording and decoding, the touching list and its
//! impulses, the blocking step-and-read, and the per-buffer reads for tests and tools.

use super::*;
use crate::buffer_pool::bytes_of;

impl GpuCollision {
    /// Records copies of what `request` asks for from the last recorded step into a staging
    /// buffer (after compacting the manifolds in contact if `touching` is asked for);
    /// variable-length data is copied for last time's count plus headroom.
    pub fn record_readback(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        request: ReadbackRequest,
    ) -> Result<ReadbackPlan, GpuError> {
        let parity = self.last_parity();
        if request.touching {
            self.touching_buffers = true;
            ensure_touching_buffers(&mut self.pool, self.pair_capacity)?;
            self.ensure_groups();
            let g = &self.groups.as_ref().expect("built above").parity[parity];
            let g = g.touching.as_ref().expect("its buffers were made above");
            let k = &self.kernels;
            let work = self.pool.get(PAIR_WORK[parity]);
            let mut timer = StageTimer::disabled(&self.ctx);
            let mut pass = timer.begin_pass(encoder, "compact_touching");
            k.count_touching
                .dispatch_work(&mut pass, &g.count_touching, work);
            k.scan_touching
                .dispatch_workgroups(&mut pass, &g.scan_touching, 1, 1);
            k.write_touching
                .dispatch_work(&mut pass, &g.write_touching, work);
        }
        let pairs = if request.pairs || request.manifolds {
            self.readback_pairs.min(self.pair_capacity)
        } else {
            0
        };
        let (touching, points) = if request.touching {
            let t = self.readback_touching.min(self.pair_capacity);
            (t, t.saturating_mul(MAX_MANIFOLD_POINTS))
        } else {
            (0, 0)
        };
        let (n, t, pts) = (u64::from(pairs), u64::from(touching), u64::from(points));
        let aabbs = bytes_of::<GpuAabb>(u64::from(self.body_count));
        let pair_points = n * u64::from(MAX_MANIFOLD_POINTS);
        let per_pair = bytes_of::<[u32; 2]>(1) + bytes_of::<GpuManifold>(1);
        let per_touching = bytes_of::<GpuTouching>(1) + bytes_of::<GpuManifold>(1);
        // Each region is padded to 8 bytes: 64 covers the padding of every region.
        let bytes = 64
            + n * per_pair
            + bytes_of::<GpuContact>(pair_points)
            + t * per_touching
            + bytes_of::<GpuContact>(pts)
            + aabbs
            + 64;
        let slot = self.readback.begin(bytes)?;
        let mut regions = Vec::new();
        let pool = &self.pool;
        let rb = &mut self.readback;
        let mut copy = |name: &'static str, bytes: u64| {
            regions.push(rb.copy(encoder, slot, pool.get(name), 0, bytes));
        };
        copy(PAIR_WORK[parity], bytes_of::<WorkList>(1));
        if request.pairs {
            copy(PAIR_A[parity][PAIR_RESULT_COPY], bytes_of::<u32>(n));
            copy(PAIR_B[parity][PAIR_RESULT_COPY], bytes_of::<u32>(n));
        }
        if request.manifolds {
            copy(MANIFOLDS[parity], bytes_of::<GpuManifold>(n));
            copy(CONTACTS[parity], bytes_of::<GpuContact>(pair_points));
        }
        if request.aabbs {
            copy(AABBS, aabbs);
        }
        if request.touching {
            copy(TOUCHING_COUNTS, bytes_of::<TouchingCounts>(1));
            copy(TOUCHING, bytes_of::<GpuTouching>(t));
            copy(TOUCHING_MANIFOLDS, bytes_of::<GpuManifold>(t));
            copy(TOUCHING_POINTS, bytes_of::<GpuContact>(pts));
        }
        Ok(ReadbackPlan {
            slot,
            request,
            parity,
            step: self.steps,
            copied_pairs: pairs,
            copied_touching: touching,
            copied_points: points,
            regions,
        })
    }

    /// Starts mapping a readback; call right after submitting the encoder it was recorded in.
    pub fn submit_readback(&mut self, plan: ReadbackPlan) -> PendingReadback {
        PendingReadback {
            ticket: self.readback.submitted(plan.slot),
            plan,
        }
    }

    /// Waits for a readback and returns its snapshot.
    pub fn receive(&mut self, pending: PendingReadback) -> Result<CollisionSnapshot, GpuError> {
        let snap = {
            let mapped = self.readback.wait_mapped(&pending.ticket)?;
            decode(&pending.plan, &mapped)?
        };
        self.finish_decode(&pending.plan, snap)
    }

    /// Sizes the next speculative copy, fetches what this one missed, trims to the count.
    fn finish_decode(
        &mut self,
        plan: &ReadbackPlan,
        mut snap: CollisionSnapshot,
    ) -> Result<CollisionSnapshot, GpuError> {
        let count = snap.work.count;
        let headroom = (count as f32 * READBACK_HEADROOM) as u32;
        self.readback_pairs = count.saturating_add(headroom).max(READBACK_MIN_PAIRS);
        let r = &plan.request;
        if count > plan.copied_pairs && (r.pairs || r.manifolds) {
            self.fetch_rest(plan, &mut snap)?;
        }
        let n = count as usize;
        snap.pairs.truncate(n);
        snap.manifolds.truncate(n);
        snap.contacts.truncate(n * MAX_MANIFOLD_POINTS as usize);
        if r.touching {
            let t = snap.touching_counts;
            let headroom = (t.manifolds as f32 * READBACK_HEADROOM) as u32;
            self.readback_touching = t.manifolds.saturating_add(headroom).max(READBACK_MIN_PAIRS);
            if t.manifolds > plan.copied_touching || t.points > plan.copied_points {
                self.fetch_rest_touching(plan, &mut snap)?;
            }
            snap.touching.touching.truncate(t.manifolds as usize);
            snap.touching.manifolds.truncate(t.manifolds as usize);
            snap.touching.points.truncate(t.points as usize);
            self.last_touching = t;
        }
        Ok(snap)
    }

    /// Blocking copy of the dense list's part a speculative readback did not cover (valid
    /// until the next readback compacts again).
    fn fetch_rest_touching(
        &self,
        plan: &ReadbackPlan,
        snap: &mut CollisionSnapshot,
    ) -> Result<(), GpuError> {
        let t = snap.touching_counts;
        let (from, to) = (u64::from(plan.copied_touching), u64::from(t.manifolds));
        let list = &mut snap.touching;
        list.touching
            .append(&mut self.read_range(TOUCHING, from, to)?);
        list.manifolds
            .append(&mut self.read_range(TOUCHING_MANIFOLDS, from, to)?);
        let (from, to) = (u64::from(plan.copied_points), u64::from(t.points));
        list.points
            .append(&mut self.read_range(TOUCHING_POINTS, from, to)?);
        Ok(())
    }

    /// Blocking read of elements `from..to` of buffer `name` (none when `to <= from`).
    fn read_range<T: bytemuck::Pod>(
        &self,
        name: &'static str,
        from: u64,
        to: u64,
    ) -> Result<Vec<T>, GpuError> {
        self.ctx
            .read_buffer(self.pool.get(name), from, to.saturating_sub(from))
    }

    /// Writes impulses given in the dense point order of the last `touching` readback (a CPU
    /// solver's results) into the last step's per-pair points, on the GPU, so the next step's
    /// `carry_impulses` warm starts them. Only the impulse fields of `impulses` are used.
    pub fn store_touching_impulses(&mut self, impulses: &[GpuContact]) -> Result<(), GpuError> {
        let t = self.last_touching;
        if impulses.len() != t.points as usize {
            return Err(GpuError::InvalidInput {
                field: "store_touching_impulses.impulses.len()".into(),
                value: format!(
                    "{} (the last touching readback had {} points)",
                    impulses.len(),
                    t.points
                ),
            });
        }
        if t.manifolds == 0 {
            return Ok(());
        }
        let bytes = std::mem::size_of_val(impulses) as u64;
        self.pool
            .ensure(IMPULSE_UPLOAD, bytes, crate::buffer_pool::STORAGE_USAGE)?;
        let queue = &self.ctx.queue;
        queue.write_buffer(
            self.pool.get(IMPULSE_UPLOAD),
            0,
            bytemuck::cast_slice(impulses),
        );
        let params = ScatterParams {
            count: t.manifolds,
            ..Default::default()
        };
        queue.write_buffer(
            self.pool.get(SCATTER_PARAMS),
            0,
            bytemuck::bytes_of(&params),
        );
        let parity = self.last_parity();
        let group = self
            .kernels
            .scatter_impulses
            .bind_named(&self.ctx, |name| match name {
                "params" => self.pool.get(SCATTER_PARAMS),
                "contacts" => self.pool.get(CONTACTS[parity]),
                name => self.pool.get(name),
            });
        let mut encoder = self.ctx.encoder("collision step");
        let mut timer = StageTimer::disabled(&self.ctx);
        let mut pass = timer.begin_pass(&mut encoder, "scatter_impulses");
        let kernel = &self.kernels.scatter_impulses;
        kernel.dispatch(&mut pass, &group, t.manifolds);
        drop(pass);
        self.ctx.submit(encoder)?;
        Ok(())
    }

    /// Blocking copy of the pairs a speculative readback did not cover. Only valid while the
    /// step's pair set has not been overwritten (fewer than two steps recorded since).
    fn fetch_rest(
        &self,
        plan: &ReadbackPlan,
        snap: &mut CollisionSnapshot,
    ) -> Result<(), GpuError> {
        if self.steps >= plan.step + 2 {
            return Err(GpuError::Device(format!(
                "readback of step {} received after its pair buffers were reused",
                plan.step
            )));
        }
        let (from, to) = (u64::from(plan.copied_pairs), u64::from(snap.work.count));
        let p = plan.parity;
        if plan.request.pairs {
            let a: Vec<u32> = self.read_range(PAIR_A[p][PAIR_RESULT_COPY], from, to)?;
            let b: Vec<u32> = self.read_range(PAIR_B[p][PAIR_RESULT_COPY], from, to)?;
            snap.pairs.extend(a.into_iter().zip(b));
        }
        if plan.request.manifolds {
            snap.manifolds
                .append(&mut self.read_range(MANIFOLDS[p], from, to)?);
            let per = u64::from(MAX_MANIFOLD_POINTS);
            let mut contacts = self.read_range(CONTACTS[p], from * per, to * per)?;
            snap.contacts.append(&mut contacts);
        }
        Ok(())
    }

    /// Runs one step and waits for `request`'s outputs. On a pair overflow with
    /// `auto_grow`, grows the pair buffers and runs the step again (without history).
    pub fn step_and_read(
        &mut self,
        request: ReadbackRequest,
    ) -> Result<CollisionSnapshot, GpuError> {
        let snap = self.step_and_read_once(request)?;
        if let Err(overflow) = snap.check_overflow() {
            if !self.config.auto_grow {
                return Err(overflow);
            }
            let requested = snap.work.requested;
            let grown = requested
                .saturating_add((requested as f32 * GROWTH_HEADROOM) as u32)
                .min(self.max_pairs())
                .max(requested);
            // Redo the same step in the same pair set: roll the step counter back.
            self.steps -= 1;
            self.reserve_pairs(grown)?;
            let again = self.step_and_read_once(request)?;
            again.check_overflow()?;
            return Ok(again);
        }
        Ok(snap)
    }

    fn step_and_read_once(
        &mut self,
        request: ReadbackRequest,
    ) -> Result<CollisionSnapshot, GpuError> {
        let mut encoder = self.ctx.encoder("collision step");
        self.record(&mut encoder, &mut StageTimer::disabled(&self.ctx))?;
        let plan = self.record_readback(&mut encoder, request)?;
        self.ctx.submit(encoder)?;
        let pending = self.submit_readback(plan);
        self.receive(pending)
    }

    /// Overwrites the last step's contact points from point `first_point` on (point index
    /// `pair * MAX_MANIFOLD_POINTS + slot`), typically to store a CPU solver's impulses so
    /// that the next step carries them over.
    pub fn store_contacts(
        &mut self,
        first_point: u32,
        points: &[GpuContact],
    ) -> Result<(), GpuError> {
        let capacity = u64::from(self.pair_capacity) * u64::from(MAX_MANIFOLD_POINTS);
        if u64::from(first_point) + points.len() as u64 > capacity {
            return Err(GpuError::InvalidInput {
                field: "store_contacts.first_point".into(),
                value: format!(
                    "{first_point} + {} points past {capacity} slots",
                    points.len()
                ),
            });
        }
        let offset = u64::from(first_point) * std::mem::size_of::<GpuContact>() as u64;
        self.ctx.queue.write_buffer(
            self.pool.get(CONTACTS[self.last_parity()]),
            offset,
            bytemuck::cast_slice(points),
        );
        Ok(())
    }

    /// Blocking read of the last step's manifolds in their body A's frame, one per pair (tests
    /// and tools; meaningful where the manifold has points).
    pub fn read_local_manifolds(&self) -> Result<Vec<GpuLocalManifold>, GpuError> {
        let p = self.last_parity();
        let count: Vec<WorkList> = self.read_range(PAIR_WORK[p], 0, 1)?;
        let n = count.first().map_or(0, |w| w.count.min(self.pair_capacity));
        self.read_range(LOCAL_MANIFOLDS[p], 0, u64::from(n))
    }

    /// Blocking read of the last step's AABBs (tests and tools).
    pub fn read_aabbs(&self) -> Result<Vec<GpuAabb>, GpuError> {
        self.read_range(AABBS, 0, u64::from(self.body_count))
    }

    /// Blocking read of the last step's sweep axis (tests and tools).
    pub fn read_sweep_axis(&self) -> Result<SweepAxis, GpuError> {
        Ok(self.ctx.read_buffer(self.pool.get(SWEEP_AXIS), 0, 1)?[0])
    }

    /// Blocking read of the last step's boxes in sweep order (tests and tools).
    pub fn read_sweep_boxes(&self) -> Result<Vec<GpuSweepBox>, GpuError> {
        self.read_range(SWEEP_BOXES, 0, u64::from(self.body_count))
    }

    /// Blocking read of the last step's body order along the sweep axis (tests and tools).
    pub fn read_sorted_bodies(&self) -> Result<(Vec<u32>, Vec<u32>), GpuError> {
        let n = u64::from(self.body_count);
        Ok((
            self.read_range(SORT_KEYS[BODY_RESULT_COPY], 0, n)?,
            self.read_range(SORT_BODIES[BODY_RESULT_COPY], 0, n)?,
        ))
    }
}
