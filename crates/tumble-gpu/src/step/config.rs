//! Settings of a [`super::GpuWorld`].

use tumble_geometry::{Real, Vec3};
use tumble_solver::SolverConfig;

use crate::GpuError;
use crate::collision::CollisionConfig;
use crate::error::invalid;
use crate::solver::{FusedMemory, SolvePath, SubstepDispatch, WarmStartSweep, WorldGrouping};

/// How each step chooses between the wide and the fused solver paths.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathPolicy {
    /// By the manifold count of a recent step ([`crate::solver::SolvePath::choose`]).
    Auto,
    /// Always this path (for tests and benchmarks).
    Always(SolvePath),
}

/// How many graph colors each pass of the wide solver path dispatches one by one
/// ([`crate::solver::GpuSolver::set_color_dispatches`]); the same bits either way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ColorDispatch {
    /// As many as a recent step used (read two steps late with the step's stats); the colors
    /// beyond, if a step uses more, go to the pass's closing single-thread dispatch.
    #[default]
    InUse,
    /// Every graph color, used or not (what the wide path did before; for measuring).
    All,
    /// The first this many graph colors, whatever the step uses (`First(0)` sends every color
    /// through the closing dispatch; for tests and measuring).
    First(u32),
}

/// Everything a GPU world needs besides its bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuWorldConfig {
    /// Gravity, m/s².
    pub gravity: Vec3,
    /// Step length, s.
    pub dt: Real,
    /// Speculative margin, m (AABB growth and the narrow phase's reporting distance).
    pub margin: Real,
    /// Contact recycling, m ([`CollisionConfig::recycle_distance`]; 0: every manifold
    /// afresh).
    pub recycle_distance: Real,
    /// Solver settings, as for the CPU solver.
    pub solver: SolverConfig,
    /// Wide or fused solver path.
    pub path: PathPolicy,
    /// Pair slots allocated per body (more pairs than that overflow and grow the buffers).
    pub pairs_per_body: u32,
    /// Pair slots allocated at least.
    pub min_pair_capacity: u32,
    /// Time each stage with GPU timestamps when the device has them.
    pub timestamps: bool,
    /// Skip the work of steps that would repeat an idle step (every body asleep or fixed, no
    /// contact, no change by the host since; see [`super::idle`]). The results are the same
    /// bit for bit either way; off records every stage of every step (for measuring it).
    pub skip_idle_steps: bool,
    /// Where the fused solve path keeps the bodies ([`FusedMemory`]; the same bits either way).
    pub fused_memory: FusedMemory,
    /// How a batch's worlds share the workgroups of [`crate::solver::SolvePath::Worlds`]
    /// ([`WorldGrouping`]; the same bits either way).
    pub world_grouping: WorldGrouping,
    /// How many colors the wide path dispatches one by one ([`ColorDispatch`]; the same bits
    /// either way).
    pub color_dispatch: ColorDispatch,
    /// How the wide path's warm start visits the graph colors ([`WarmStartSweep`]; the same
    /// bits either way).
    pub warm_start_sweep: WarmStartSweep,
    /// How the wide path dispatches its substeps: per color and pass, or all in one dispatch
    /// ([`SubstepDispatch`]; the same bits either way).
    pub substep_dispatch: SubstepDispatch,
}

impl Default for GpuWorldConfig {
    /// Earth gravity along -y, 60 Hz, the collision stages' default margin and pair
    /// capacity, the default soft-step solver, automatic path, idle steps skipped.
    fn default() -> Self {
        let collision = CollisionConfig::default();
        Self {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            dt: collision.dt,
            margin: collision.margin,
            recycle_distance: collision.recycle_distance,
            solver: SolverConfig::default(),
            path: PathPolicy::Auto,
            pairs_per_body: collision.pairs_per_body,
            min_pair_capacity: collision.min_pair_capacity,
            timestamps: false,
            skip_idle_steps: true,
            fused_memory: FusedMemory::Auto,
            world_grouping: WorldGrouping::Auto,
            color_dispatch: ColorDispatch::InUse,
            warm_start_sweep: WarmStartSweep::Auto,
            substep_dispatch: SubstepDispatch::Auto,
        }
    }
}

impl GpuWorldConfig {
    /// Checks every field; the error names the first bad one and its value.
    pub fn validate(&self) -> Result<(), GpuError> {
        if !self.gravity.iter().all(|g| g.is_finite()) {
            return Err(invalid("gravity", self.gravity));
        }
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(invalid("dt", self.dt));
        }
        if let ColorDispatch::First(colors) = self.color_dispatch
            && colors > crate::solver::constants::GRAPH_COLOR_COUNT
        {
            return Err(invalid("color_dispatch", self.color_dispatch));
        }
        if !(self.margin.is_finite() && self.margin >= 0.0) {
            return Err(invalid("margin", self.margin));
        }
        crate::collision::validate::check_recycle_distance(
            "recycle_distance",
            self.recycle_distance,
        )?;
        if self.pairs_per_body == 0 {
            return Err(invalid("pairs_per_body", self.pairs_per_body));
        }
        self.substep_dispatch.validate("substep_dispatch")?;
        self.solver.validate().map_err(|e| GpuError::InvalidInput {
            field: e.field.to_string(),
            value: format!("{} (expected {})", e.value, e.expected),
        })
    }

    /// The collision stages' settings.
    pub fn collision(&self) -> CollisionConfig {
        CollisionConfig {
            margin: self.margin,
            dt: self.dt,
            pairs_per_body: self.pairs_per_body,
            min_pair_capacity: self.min_pair_capacity,
            auto_grow: false,
            recycle_distance: self.recycle_distance,
            compact_fresh_pairs: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{ColorDispatch, GpuWorldConfig};
    use crate::GpuError;
    use crate::solver::constants::GRAPH_COLOR_COUNT;

    #[test]
    fn more_colors_one_by_one_than_there_are_is_refused_by_name() {
        let with = |color_dispatch| GpuWorldConfig {
            color_dispatch,
            ..Default::default()
        };
        // Every count up to the graph colors is a valid setting (First(0): all in the tail).
        for k in [0, 1, GRAPH_COLOR_COUNT] {
            assert!(with(ColorDispatch::First(k)).validate().is_ok(), "{k}");
        }
        // One more would name a color that does not exist: refused, not clamped.
        match with(ColorDispatch::First(GRAPH_COLOR_COUNT + 1)).validate() {
            Err(GpuError::InvalidInput { field, value }) => {
                assert_eq!(field, "color_dispatch");
                assert!(value.contains("25"), "{value}");
            }
            other => panic!("expected an InvalidInput error, got {other:?}"),
        }
    }

    #[test]
    fn a_one_dispatch_workgroup_count_beyond_the_dispatch_limit_is_refused_by_name() {
        use crate::solver::SubstepDispatch;
        let with = |groups| GpuWorldConfig {
            substep_dispatch: SubstepDispatch::OneDispatch { groups },
            ..Default::default()
        };
        for groups in [None, Some(1), Some(65_535)] {
            assert!(with(groups).validate().is_ok(), "{groups:?}");
        }
        // Zero workgroups run nothing, and 65,536 is past wgpu's limit per dimension: refused,
        // not clamped.
        for groups in [0, 65_536] {
            match with(Some(groups)).validate() {
                Err(GpuError::InvalidInput { field, value }) => {
                    assert_eq!(field, "substep_dispatch.groups");
                    assert!(value.starts_with(&groups.to_string()), "{value}");
                }
                other => panic!("expected an InvalidInput error, got {other:?}"),
            }
        }
    }

    #[test]
    fn a_recycle_distance_outside_the_facades_bound_is_refused_by_name() {
        let with = |recycle_distance| GpuWorldConfig {
            recycle_distance,
            ..Default::default()
        };
        // 0 (off), the default and the facade's largest are settings.
        for d in [0.0, 1e-3, tumble_solver::bounds::MAX_RECYCLE_DISTANCE] {
            assert!(with(d).validate().is_ok(), "{d}");
        }
        // Negative, past the bound (a slide that large is no longer the same contact), or not
        // a number: refused, not clamped or turned off.
        for d in [-1e-3, 0.02, f32::NAN, f32::INFINITY] {
            match with(d).validate() {
                Err(GpuError::InvalidInput { field, value }) => {
                    assert_eq!(field, "recycle_distance");
                    assert_eq!(value, d.to_string(), "{d}");
                }
                other => panic!("{d}: expected an InvalidInput error, got {other:?}"),
            }
        }
    }
}
