//! Idle steps: a step that moves no body, forms no contact and starts from none changes
//! nothing on the GPU, so the steps after it, until the host changes something, would repeat
//! it bit for bit. [`IdleSteps`] finds such a step in the lagged step stats and lets
//! [`super::GpuWorld::step`] skip the work of the steps that follow (it still records the
//! stats copy and the requested reads, so readers see the same results).
//!
//! Why a skipped step equals a recorded one: with every body fixed or asleep (a sleeping body
//! is fixed to the kernels), the wake stage wakes nothing (no island was flagged, or some body
//! would move), the collision stages recompute the same boxes from the same poses and form no
//! pair (pairs among fixed and sleeping bodies are never formed), the carry has no manifold to
//! read, the solver leaves fixed bodies' poses and velocities untouched, and the sleep stage
//! freezes sleeping bodies' rest times and starts no island search. Every buffer a later step
//! reads is then what the step before left. The decision reads exact counts, never timing, so
//! whether a step is skipped does not depend on how fast the device is;
//! `idle_steps_are_skipped_and_step_bit_for_bit_like_recorded_ones` in
//! `tests/tests/gpu_sleep.rs` compares skipping against recording every step, bit for bit.

use super::stats_ring::StepStats;

/// Tracks host changes and the lagged stats; answers whether the next step may be skipped.
#[derive(Clone, Copy, Debug, Default)]
pub struct IdleSteps {
    /// Host calls that changed the world's state (poses, velocities, impulses, wakes,
    /// bodies, effects, solver settings), counted.
    changes: u64,
    /// The manifold count of the step before the one last observed.
    previous_count: Option<u32>,
    /// Whether the step last observed was idle and nothing changed after it was recorded.
    idle: bool,
    /// Steps skipped so far.
    skipped: u64,
}

impl IdleSteps {
    /// Counts a change made by the host.
    pub fn changed(&mut self) {
        self.changes += 1;
        self.idle = false;
    }

    /// The change count, recorded with each step's stats.
    pub fn changes(&self) -> u64 {
        self.changes
    }

    /// Takes the stats of the next lagged step, in step order (`None`: none pending, after
    /// the bodies were uploaded again).
    pub fn observe(&mut self, stats: Option<&StepStats>) {
        let Some(stats) = stats else {
            self.previous_count = None;
            self.idle = false;
            return;
        };
        self.idle = stats.active == Some(0)
            && stats.work.count == 0
            && self.previous_count == Some(0)
            && stats.changes == self.changes;
        self.previous_count = Some(stats.work.count);
    }

    /// True when the next step would repeat an idle step exactly.
    pub fn can_skip(&self) -> bool {
        self.idle
    }

    /// Counts a skipped step.
    pub fn skipped(&mut self) {
        self.skipped += 1;
    }

    /// Steps skipped so far.
    pub fn skipped_steps(&self) -> u64 {
        self.skipped
    }

    /// The tracker's state, for a saved world.
    pub(crate) fn save(&self) -> super::SavedIdle {
        super::SavedIdle {
            changes: self.changes,
            previous_count: self.previous_count,
            idle: self.idle,
            skipped: self.skipped,
        }
    }

    /// The tracker a saved world had.
    pub(crate) fn from_saved(s: super::SavedIdle) -> Self {
        Self {
            changes: s.changes,
            previous_count: s.previous_count,
            idle: s.idle,
            skipped: s.skipped,
        }
    }
}
