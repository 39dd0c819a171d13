//! The collision stages' state between steps, saved and loaded (see
//! `crate::step::GpuWorldState`).

use super::GpuCollision;
use super::buffers::{TOUCHING, TOUCHING_BUFFERS};
use crate::GpuError;
use crate::buffer_pool::BufferPool;
use crate::step::SavedCollision;

impl GpuCollision {
    /// Everything the next step reads: the buffers (poses, velocities, shapes, groups, both
    /// pair parities with their manifolds, points and impulses), the parity and the pair
    /// capacity (blocking).
    pub fn save_state(&self) -> Result<SavedCollision, GpuError> {
        Ok(SavedCollision {
            body_count: self.body_count,
            pair_capacity: self.pair_capacity,
            long_extent: self.long_extent,
            steps: self.steps,
            history_resets: self.history_resets,
            buffers: if self.body_count == 0 {
                Vec::new()
            } else {
                self.pool.save()?
            },
        })
    }

    /// Takes the state [`Self::save_state`] gave, sizing the buffers as it says. Errs when
    /// it does not fit this stage (a buffer it does not hold, a size the device cannot bind,
    /// more bodies than the engine takes), naming the part.
    pub fn load_state(&mut self, saved: &SavedCollision) -> Result<(), GpuError> {
        if saved.body_count > crate::MAX_BODIES {
            return Err(GpuError::InvalidInput {
                field: "saved body_count".into(),
                value: saved.body_count.to_string(),
            });
        }
        if saved.body_count > 0 {
            self.long_extent = saved.long_extent;
            // The dense touching list is held as the saved stage held it, so that both pools
            // name the same buffers.
            let touching = saved.buffers.iter().any(|b| b.name == TOUCHING);
            if !touching {
                self.pool.remove(&TOUCHING_BUFFERS);
            }
            self.touching_buffers = touching;
            self.allocate(saved.body_count, saved.pair_capacity, false)?;
            self.pool.load(&saved.buffers)?;
        }
        self.steps = saved.steps;
        self.history_resets = saved.history_resets;
        Ok(())
    }

    /// The steps recorded and the history resets (the parity and the event stage's check).
    pub(crate) fn step_state(&self) -> (u64, u64) {
        (self.steps, self.history_resets)
    }

    /// Puts back what [`Self::step_state`] gave (a step undone).
    pub(crate) fn set_step_state(&mut self, (steps, history_resets): (u64, u64)) {
        self.steps = steps;
        self.history_resets = history_resets;
    }

    /// The bodies' `WorkList` (count = bodies).
    pub(crate) fn body_work(&self) -> &wgpu::Buffer {
        self.pool.get(super::buffers::BODY_WORK)
    }

    /// Records a copy of the state buffers into `shadow` ([`BufferPool::record_checkpoint`]).
    pub(crate) fn record_checkpoint(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        shadow: &mut BufferPool,
    ) {
        self.pool.record_checkpoint(encoder, shadow);
    }

    /// Records the copy of `shadow` back ([`BufferPool::copy_back`]).
    pub(crate) fn copy_back(&self, encoder: &mut wgpu::CommandEncoder, shadow: &BufferPool) {
        self.pool.copy_back(encoder, shadow);
    }
}
