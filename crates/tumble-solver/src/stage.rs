//! The stages of one step, in the order every backend runs them.
//!
//! As Box2D v3's `b2SolverStageType` names the stages its solver walks, [`Stage`] names the
//! stages of Tumble's step, written once: the CPU step loop walks [`Stage::ALL`], the
//! facade's per-stage timings are indexed by it, and the GPU recorder's timestamp names are
//! [`Stage::name`]s (a GPU stage split into several kernels, such as the solve's substep
//! passes, is timed under its stage's name).

/// One stage of the step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Stage {
    /// Poses and velocities to AABBs grown by the margin and the step's motion
    /// (`tumble_broad::update_aabbs`).
    UpdateAabbs,
    /// AABBs to candidate pairs, pairs of two immovable bodies left out
    /// (`tumble_broad::BroadPhase`).
    BroadPhase,
    /// Candidate pairs to contact manifolds, warm-started from the contact cache
    /// ([`crate::stages::narrow_phase`]).
    NarrowPhase,
    /// Manifolds to graph colors, top of a pile first ([`crate::stages::color`]).
    Color,
    /// The solver: prepare, substeps of integration and contact passes, restitution, stored
    /// impulses ([`crate::solve_with_effects`]).
    Solve,
    /// Displacements into poses, impulses into the contact cache ([`crate::stages::finish`]).
    Finish,
    /// Rest timers, islands, and the islands that fall asleep ([`crate::SleepState`]).
    Sleep,
}

impl Stage {
    /// Every stage, in step order.
    pub const ALL: [Stage; 7] = [
        Stage::UpdateAabbs,
        Stage::BroadPhase,
        Stage::NarrowPhase,
        Stage::Color,
        Stage::Solve,
        Stage::Finish,
        Stage::Sleep,
    ];

    /// Number of stages.
    pub const COUNT: usize = Self::ALL.len();

    /// The stage's position in [`Stage::ALL`].
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The stage's name as in docs/architecture.md (`update_aabbs`, `broad_phase`, ...), also
    /// the name the GPU's stage timestamps carry.
    pub const fn name(self) -> &'static str {
        match self {
            Stage::UpdateAabbs => "update_aabbs",
            Stage::BroadPhase => "broad_phase",
            Stage::NarrowPhase => "narrow_phase",
            Stage::Color => "color",
            Stage::Solve => "solve",
            Stage::Finish => "finish",
            Stage::Sleep => "sleep",
        }
    }

    /// The stage named `name` (see [`Stage::name`]), if any.
    pub fn from_name(name: &str) -> Option<Stage> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_lists_each_stage_once_in_step_order() {
        assert_eq!(Stage::COUNT, 7);
        for (i, s) in Stage::ALL.into_iter().enumerate() {
            assert_eq!(s.index(), i);
            assert_eq!(Stage::from_name(s.name()), Some(s));
        }
        assert!(Stage::ALL.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(Stage::ALL[0].name(), "update_aabbs");
        assert_eq!(Stage::ALL[6], Stage::Sleep);
        assert_eq!(Stage::from_name("prepare"), None);
    }
}
