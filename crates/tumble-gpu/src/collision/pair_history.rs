//! Last step's pair list edited between steps for a batch of worlds: some worlds' pairs
//! dropped (a reset), or every pair renumbered after the bodies were uploaded in a new order.

use super::GpuCollision;
use super::buffers::*;
use crate::GpuError;

impl GpuCollision {
    /// Drops the pairs of some worlds from last step's list, so the next step carries no
    /// impulses, hysteresis or color seeds for them and the other worlds keep theirs.
    /// `forget[w]` is 0 to keep world `w`'s pairs, else its first body plus one
    /// (`forget_pairs.wgsl`). Errs unless `forget` has one entry per world.
    pub fn forget_worlds(&mut self, forget: &[u32]) -> Result<(), GpuError> {
        if self.steps == 0 || forget.iter().all(|&f| f == 0) {
            return Ok(());
        }
        let bytes: &[u8] = bytemuck::cast_slice(forget);
        self.pool.ensure(
            FORGET_WORLDS,
            bytes.len() as u64,
            crate::buffer_pool::STORAGE_USAGE,
        )?;
        self.ctx
            .queue
            .write_buffer(self.pool.get(FORGET_WORLDS), 0, bytes);
        let q = self.last_parity();
        let b = |name: &'static str| self.pool.get(name);
        let group = self
            .kernels
            .forget_pairs
            .bind_named(&self.ctx, |name| match name {
                "previous_work" => b(PAIR_WORK[q]),
                "previous_a" => b(PAIR_A[q][PAIR_RESULT_COPY]),
                "previous_b" => b(PAIR_B[q][PAIR_RESULT_COPY]),
                "forget" => b(FORGET_WORLDS),
                name => b(name),
            });
        self.submit_one("forget_pairs", |pass| {
            self.kernels
                .forget_pairs
                .dispatch_work(pass, &group, b(PAIR_WORK[q]));
        });
        Ok(())
    }

    /// Renumbers last step's pairs through `remap` (`remap_pairs.wgsl`).
    pub(super) fn remap_pairs(&mut self, remap: &[u32]) -> Result<(), GpuError> {
        if self.steps == 0 || remap.is_empty() {
            return Ok(());
        }
        let bytes: &[u8] = bytemuck::cast_slice(remap);
        self.pool
            .ensure(REMAP, bytes.len() as u64, crate::buffer_pool::STORAGE_USAGE)?;
        self.ctx.queue.write_buffer(self.pool.get(REMAP), 0, bytes);
        let q = self.last_parity();
        let b = |name: &'static str| self.pool.get(name);
        let group = self
            .kernels
            .remap_pairs
            .bind_named(&self.ctx, |name| match name {
                "previous_work" => b(PAIR_WORK[q]),
                "previous_a" => b(PAIR_A[q][PAIR_RESULT_COPY]),
                "previous_b" => b(PAIR_B[q][PAIR_RESULT_COPY]),
                "remap" => b(REMAP),
                name => b(name),
            });
        self.submit_one("remap_pairs", |pass| {
            self.kernels
                .remap_pairs
                .dispatch_work(pass, &group, b(PAIR_WORK[q]));
        });
        Ok(())
    }

    /// Records one compute pass with `record` and submits it.
    fn submit_one(&self, label: &'static str, record: impl FnOnce(&mut wgpu::ComputePass<'_>)) {
        let mut encoder = self
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: None,
            });
            record(&mut pass);
        }
        self.ctx.queue.submit([encoder.finish()]);
    }
}
