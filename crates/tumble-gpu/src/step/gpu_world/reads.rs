//! [`GpuWorld`]'s reads: the copies a step records for the host (double-buffered, read
//! without stalling the next step) and blocking reads of the current state.

use super::*;
use crate::buffer_pool::bytes_of;
use crate::kernels::contact_summary::CONTACT_SUMMARY_BYTES;

impl GpuWorld {
    /// Asks the next steps to copy `request` for reading (see [`Self::wait_snapshot`]).
    pub fn request_reads(&mut self, request: ReadRequest) {
        self.request = request;
    }

    /// Records copies of `request` (with up to `manifolds` manifolds) into a staging slot.
    pub(super) fn record_read(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        request: ReadRequest,
        manifolds: u32,
    ) -> Result<(usize, Vec<Region>, bool), GpuError> {
        let n = self.bodies.len() as u64;
        let summary = if request.summary {
            Some(self.record_summary(encoder)?)
        } else {
            None
        };
        let (manifold_buffer, point_buffer, work, capacity) = self.contact_buffers();
        let m = u64::from(manifolds.min(capacity));
        let buffers = self.collision.buffers(self.pool.get(BODIES));
        // What to copy, in the order `decode` reads it, with each copy's bytes.
        let mut copies: Vec<(&wgpu::Buffer, u64)> = Vec::new();
        if request.poses {
            copies.push((buffers.poses, bytes_of::<GpuPose>(n)));
        }
        if request.velocities {
            copies.push((buffers.velocities, bytes_of::<GpuVelocity>(n)));
        }
        if request.contacts {
            copies.extend([
                (&work, bytes_of::<WorkList>(1)),
                (&manifold_buffer, bytes_of::<GpuManifold>(m)),
                (
                    &point_buffer,
                    bytes_of::<GpuContact>(m * u64::from(MAX_MANIFOLD_POINTS)),
                ),
                (self.solver.tilts(), bytes_of::<GpuTilt>(m)),
            ]);
        }
        let islands = self.sleep.island_labels().filter(|_| request.sleeping);
        if let Some(islands) = islands {
            copies.push((islands, bytes_of::<u32>(n)));
        }
        if let Some(summary) = &summary {
            copies.push((summary, CONTACT_SUMMARY_BYTES));
        }
        // Alignment slack per region.
        let slack = 2 * wgpu::MAP_ALIGNMENT;
        let slot = self
            .readback
            .begin(copies.iter().map(|&(_, len)| len + slack).sum())?;
        let regions: Vec<Region> = copies
            .into_iter()
            .map(|(buffer, len)| self.readback.copy(encoder, slot, buffer, 0, len))
            .collect();
        self.bytes_read += regions.iter().map(|r| r.len).sum::<u64>();
        Ok((slot, regions, islands.is_some()))
    }

    /// Waits for the most recent requested read (older ones are dropped).
    pub fn wait_snapshot(&mut self) -> Result<Option<Snapshot>, GpuError> {
        while self.pending.len() > 1 {
            self.pending.pop_front();
        }
        let Some(last) = self.pending.pop_front() else {
            return Ok(None);
        };
        // `wait` polls until the map callback has run: another user of the device may be
        // running it in its own poll when a plain wait returns.
        let bytes = self.readback.wait(&last.ticket, &last.regions)?;
        Ok(Some(decode(&last, self.bodies.len(), bytes)))
    }

    /// Reads `request` from the current state now, blocking (queued impulses are applied
    /// first). Contacts are the last step's, complete.
    pub fn read_now(&mut self, request: ReadRequest) -> Result<Snapshot, GpuError> {
        self.flush_impulses()?;
        let n = self.bodies.len() as u64;
        let mut snapshot = Snapshot {
            step: self.steps,
            ..Default::default()
        };
        if n == 0 {
            return Ok(snapshot);
        }
        let buffers = self.collision.buffers(self.pool.get(BODIES));
        if request.poses {
            snapshot.poses = self.ctx.read_buffer(buffers.poses, 0, n)?;
        }
        if request.velocities {
            snapshot.velocities = self.ctx.read_buffer(buffers.velocities, 0, n)?;
        }
        if request.contacts && self.steps > 0 {
            let (manifolds, points, work, _) = self.contact_buffers();
            let list: Vec<WorkList> = self.ctx.read_buffer(&work, 0, 1)?;
            let count = u64::from(list[0].count);
            snapshot.contacts = Some(ContactSnapshot {
                work: list[0],
                manifolds: self.ctx.read_buffer(&manifolds, 0, count)?,
                points: self
                    .ctx
                    .read_buffer(&points, 0, count * u64::from(MAX_MANIFOLD_POINTS))?,
                tilts: self.ctx.read_buffer(self.solver.tilts(), 0, count)?,
            });
        }
        self.bytes_read += snapshot_bytes(&snapshot);
        if request.sleeping {
            snapshot.sleeping = match self.sleep.island_labels() {
                Some(islands) => {
                    let labels: Vec<u32> = self.ctx.read_buffer(islands, 0, n)?;
                    self.bytes_read += std::mem::size_of_val(labels.as_slice()) as u64;
                    labels.iter().map(|&l| l != AWAKE).collect()
                }
                None => vec![false; n as usize],
            };
        }
        if request.summary {
            snapshot.summary = self.read_summary_now()?;
        }
        Ok(snapshot)
    }
}

/// Bytes held by a snapshot's arrays.
fn snapshot_bytes(s: &Snapshot) -> u64 {
    fn bytes<T>(v: &[T]) -> u64 {
        std::mem::size_of_val(v) as u64
    }
    let contacts = s.contacts.as_ref().map_or(0, |c| {
        std::mem::size_of::<WorkList>() as u64
            + bytes(&c.manifolds)
            + bytes(&c.points)
            + bytes(&c.tilts)
    });
    bytes(&s.poses) + bytes(&s.velocities) + contacts
}
