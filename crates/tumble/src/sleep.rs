//! Sleep: an island (dynamic bodies touching through dynamic bodies, see
//! [`tumble_solver::Islands`]) whose bodies have all stayed slow for [`TIME_TO_SLEEP`] leaves
//! the step; it wakes when an awake body touches it, when a moving kinematic body's box
//! reaches it, or when the user sets a pose or a velocity, applies an impulse, or removes one
//! of its bodies. The rules and their state are [`tumble_solver::SleepState`].
//!
//! `Backend::Cpu` and `Backend::Hybrid` run the CPU sleep stage on the solved results; on
//! `Backend::Gpu` the islands are found and put to sleep on the GPU (`tumble_gpu::sleep`,
//! label propagation instead of union-find, the same thresholds), and `is_sleeping` and
//! `sleeping_count` read its flags back lazily like any other result.

use crate::{BodyHandle, Error, World};

pub use tumble_solver::{ANGULAR_SLEEP_TOLERANCE, LINEAR_SLEEP_TOLERANCE, TIME_TO_SLEEP};

impl World {
    /// True when the body sleeps (it is out of the step until something wakes its island).
    pub fn is_sleeping(&self, h: BodyHandle) -> Result<bool, Error> {
        let d = self.handles.dense(h)?;
        self.backend
            .is_sleeping(&self.host, d, self.effects().sleep)
    }

    /// Bodies asleep.
    pub fn sleeping_count(&self) -> usize {
        self.backend
            .sleeping_count(&self.host, self.effects().sleep)
    }

    /// Wakes the body's island (a no-op for an awake body).
    pub fn wake_up(&mut self, h: BodyHandle) -> Result<(), Error> {
        let d = self.handles.dense(h)?;
        self.backend.wake(&mut self.host, d)
    }
}
