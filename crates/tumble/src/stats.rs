//! What the last step did: counts and per-stage CPU time.

use std::ops::{Index, IndexMut};
use std::time::Duration;

use tumble_solver::Stage;

/// Wall-clock time of each stage of the last step, by field or indexed by [`Stage`]
/// (`timings[Stage::Solve]`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StageTimings {
    /// Stage 1: AABBs.
    pub update_aabbs: Duration,
    /// Stage 2: sweep-and-prune.
    pub broad_phase: Duration,
    /// Stage 3: box-box manifolds.
    pub narrow_phase: Duration,
    /// Stage 5: graph coloring.
    pub color: Duration,
    /// Stage 6: the solver.
    pub solve: Duration,
    /// Stage 7: poses out, impulses stored.
    pub finish: Duration,
    /// Stage 8: rest timers, islands and sleep (zero while sleep is off).
    pub sleep: Duration,
}

impl StageTimings {
    /// The sum of all stages.
    pub fn total(&self) -> Duration {
        Stage::ALL.iter().map(|&s| self[s]).sum()
    }

    /// Each stage and its time, in step order.
    pub fn iter(&self) -> impl Iterator<Item = (Stage, Duration)> + '_ {
        Stage::ALL.into_iter().map(|s| (s, self[s]))
    }
}

impl Index<Stage> for StageTimings {
    type Output = Duration;

    fn index(&self, stage: Stage) -> &Duration {
        match stage {
            Stage::UpdateAabbs => &self.update_aabbs,
            Stage::BroadPhase => &self.broad_phase,
            Stage::NarrowPhase => &self.narrow_phase,
            Stage::Color => &self.color,
            Stage::Solve => &self.solve,
            Stage::Finish => &self.finish,
            Stage::Sleep => &self.sleep,
        }
    }
}

impl IndexMut<Stage> for StageTimings {
    fn index_mut(&mut self, stage: Stage) -> &mut Duration {
        match stage {
            Stage::UpdateAabbs => &mut self.update_aabbs,
            Stage::BroadPhase => &mut self.broad_phase,
            Stage::NarrowPhase => &mut self.narrow_phase,
            Stage::Color => &mut self.color,
            Stage::Solve => &mut self.solve,
            Stage::Finish => &mut self.finish,
            Stage::Sleep => &mut self.sleep,
        }
    }
}

/// Times consecutive stages of one step into a [`StageTimings`].
pub(crate) struct StageClock {
    timings: StageTimings,
    last: std::time::Instant,
}

impl StageClock {
    /// Starts the first stage now.
    pub(crate) fn start() -> Self {
        Self {
            timings: StageTimings::default(),
            last: std::time::Instant::now(),
        }
    }

    /// Ends `stage` now (adding to its time) and starts the next.
    pub(crate) fn lap(&mut self, stage: Stage) {
        let now = std::time::Instant::now();
        self.timings[stage] += now - self.last;
        self.last = now;
    }

    /// The times so far.
    pub(crate) fn timings(&self) -> StageTimings {
        self.timings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stages_index_their_own_fields_and_sum_to_the_total() {
        let mut t = StageTimings::default();
        for (k, s) in Stage::ALL.into_iter().enumerate() {
            t[s] = Duration::from_millis(1 << k);
        }
        assert_eq!(t.update_aabbs, Duration::from_millis(1));
        assert_eq!(t.narrow_phase, Duration::from_millis(4));
        assert_eq!(t.solve, Duration::from_millis(16));
        assert_eq!(t.sleep, Duration::from_millis(64));
        assert_eq!(t.total(), Duration::from_millis(127));
        let order: Vec<Stage> = t.iter().map(|(s, _)| s).collect();
        assert_eq!(order, Stage::ALL);
    }
}

/// Counts and timings of the last step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepStats {
    /// Bodies in the world.
    pub bodies: usize,
    /// Candidate pairs out of the broad phase.
    pub pairs: usize,
    /// Manifolds out of the narrow phase (touching or speculative).
    pub manifolds: usize,
    /// Of those, the ones reused from the step before (`WorldConfig::recycle_distance`), on
    /// every backend.
    pub recycled_manifolds: usize,
    /// Contact points over all manifolds.
    pub contact_points: usize,
    /// Graph colors holding at least one constraint (0 in sequential order).
    pub colors: usize,
    /// Constraints in the sequential overflow set.
    pub overflow: usize,
    /// Colors solved on the thread pool.
    pub parallel_colors: usize,
    /// Deepest overlap among the manifolds at the start of the step, m (0 when none).
    pub max_penetration: f32,
    /// Time per stage.
    pub timings: StageTimings,
}
