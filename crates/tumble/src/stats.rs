//! What the last step did: counts and per-stage CPU time.

use std::time::Duration;

/// Wall-clock time of each stage of the last step.
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
}

impl StageTimings {
    /// The sum of all stages.
    pub fn total(&self) -> Duration {
        self.update_aabbs
            + self.broad_phase
            + self.narrow_phase
            + self.color
            + self.solve
            + self.finish
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
