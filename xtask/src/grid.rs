//! The configurations a validation sweeps: solver kind x iterations or substeps x warm start
//! x backend for Tumble, and rapier3d at matched substep counts.

use std::fmt;

/// Tumble's solvers: the two kinds, and the soft step with friction in the relax passes only.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Solver {
    /// The thesis's projected Gauss-Seidel with a Baumgarte position bias; accuracy is bought
    /// with iterations.
    Baumgarte,
    /// Soft constraints solved over substeps with a relax pass; accuracy is bought with substeps.
    SoftStep,
    /// The soft step with friction in the relax passes only (`FrictionPasses::RelaxOnly`):
    /// fewer rows per substep, as rapier3d solves friction.
    SoftStepRelaxFriction,
}

/// Where Tumble runs the step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BackendChoice {
    /// Every stage on the CPU.
    Cpu,
    /// Every stage on the GPU.
    Gpu,
    /// Collision on the GPU, solver on the CPU (the thesis's fastest mix).
    Hybrid,
}

impl BackendChoice {
    /// Parses `cpu`, `gpu` or `hybrid`.
    pub fn parse(text: &str) -> Result<Self, String> {
        match text.trim().to_ascii_lowercase().as_str() {
            "cpu" => Ok(Self::Cpu),
            "gpu" => Ok(Self::Gpu),
            "hybrid" => Ok(Self::Hybrid),
            other => Err(format!(
                "--backends: unknown backend `{other}` (expected cpu, gpu or hybrid)"
            )),
        }
    }

    /// Lower-case name, as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Cpu => "cpu",
            Self::Gpu => "gpu",
            Self::Hybrid => "hybrid",
        }
    }
}

impl Solver {
    /// Lower-case name used in tables and files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Baumgarte => "baumgarte",
            Self::SoftStep => "soft_step",
            Self::SoftStepRelaxFriction => "soft_step_relax_friction",
        }
    }
}

/// One Tumble solver setting.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TumbleSetting {
    /// Which solver.
    pub solver: Solver,
    /// Velocity iterations per substep.
    pub iterations: u32,
    /// Substeps per step.
    pub substeps: u32,
    /// Whether last step's impulses seed this step's.
    pub warm_start: bool,
    /// Where the step runs.
    pub backend: BackendChoice,
    /// True for the configuration `SolverConfig::default()` gives: the one whose failure
    /// fails the validation.
    pub is_default: bool,
}

/// One engine configuration to run every scene with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RunConfig {
    /// Tumble with a solver setting.
    Tumble(TumbleSetting),
    /// rapier3d with this many solver iterations (its substeps) per step.
    Rapier {
        /// rapier's `num_solver_iterations`.
        substeps: u32,
    },
}

impl RunConfig {
    /// The engine's name: `tumble` or `rapier3d`.
    pub fn engine(&self) -> &'static str {
        match self {
            Self::Tumble(_) => "tumble",
            Self::Rapier { .. } => "rapier3d",
        }
    }

    /// The series a plot draws this configuration in: solver x backend x warm start.
    pub fn series(&self) -> String {
        match self {
            Self::Tumble(t) => format!(
                "{} {}{}",
                t.solver.name(),
                t.backend.name(),
                if t.warm_start { "" } else { " cold" }
            ),
            Self::Rapier { .. } => "rapier3d".into(),
        }
    }

    /// The knob swept along a series: iterations for Baumgarte, substeps otherwise.
    pub fn effort(&self) -> u32 {
        match self {
            Self::Tumble(t) if t.solver == Solver::Baumgarte => t.iterations * t.substeps,
            Self::Tumble(t) => t.substeps,
            Self::Rapier { substeps } => *substeps,
        }
    }

    /// True for Tumble's default configuration on the CPU.
    pub fn is_default_cpu(&self) -> bool {
        matches!(self, Self::Tumble(t) if t.is_default && t.backend == BackendChoice::Cpu)
    }
}

impl fmt::Display for RunConfig {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Tumble(t) => write!(
                f,
                "{} it{} ss{} {} {}{}",
                t.solver.name(),
                t.iterations,
                t.substeps,
                if t.warm_start { "warm" } else { "cold" },
                t.backend.name(),
                if t.is_default { " (default)" } else { "" }
            ),
            Self::Rapier { substeps } => write!(f, "rapier3d ss{substeps}"),
        }
    }
}

/// How much of the grid to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GridSize {
    /// A reduced grid on shortened scenes: minutes on two cores.
    Quick,
    /// Every combination on full-length scenes.
    Full,
}

/// Baumgarte iteration counts: powers of two, and the thesis's two settings, 5 (its GPU
/// solver) and 150 (its CPU solver).
const BAUMGARTE_ITERATIONS_FULL: &[u32] = &[1, 2, 4, 5, 8, 16, 32, 64, 150];
/// Soft-step substep counts (one iteration each, as soft-step solvers are usually run).
const SOFT_SUBSTEPS_FULL: &[u32] = &[1, 2, 4, 8, 16];
/// rapier3d solver iterations matched to the soft-step substeps.
const RAPIER_SUBSTEPS_FULL: &[u32] = &[1, 2, 4, 8, 16];

/// Quick grid, warm-started Baumgarte: from hopeless to the thesis's setting.
const BAUMGARTE_WARM_QUICK: &[u32] = &[1, 4, 16, 150];
/// Quick grid, cold Baumgarte: the thesis ran without warm starting, 5 iterations on the GPU
/// and 150 on the CPU; 16 shows what warm starting is worth in between.
const BAUMGARTE_COLD_QUICK: &[u32] = &[5, 16, 150];
/// Quick grid, warm-started soft step: every substep count.
const SOFT_WARM_QUICK: &[u32] = &[1, 2, 4, 8, 16];
/// Quick grid, cold soft step.
const SOFT_COLD_QUICK: &[u32] = &[4];
/// Quick grid, rapier3d.
const RAPIER_SUBSTEPS_QUICK: &[u32] = &[1, 2, 4, 8];
/// Quick grid, warm-started soft step with friction in the relax passes only: the counts
/// where it competes with rapier3d's iterations on time.
const SOFT_RELAX_FRICTION_QUICK: &[u32] = &[1, 2, 4];

/// The configurations to run, in a stable order: Tumble per backend, then rapier3d.
/// `default` is Tumble's default solver setting; it is always included on every backend
/// (merged into the grid point it coincides with, if any).
pub fn build_grid(
    size: GridSize,
    backends: &[BackendChoice],
    default: TumbleSetting,
) -> Vec<RunConfig> {
    let (b_warm, b_cold, s_warm, s_cold, relax_friction, rapier) = match size {
        GridSize::Quick => (
            BAUMGARTE_WARM_QUICK,
            BAUMGARTE_COLD_QUICK,
            SOFT_WARM_QUICK,
            SOFT_COLD_QUICK,
            SOFT_RELAX_FRICTION_QUICK,
            RAPIER_SUBSTEPS_QUICK,
        ),
        GridSize::Full => (
            BAUMGARTE_ITERATIONS_FULL,
            BAUMGARTE_ITERATIONS_FULL,
            SOFT_SUBSTEPS_FULL,
            SOFT_SUBSTEPS_FULL,
            SOFT_SUBSTEPS_FULL,
            RAPIER_SUBSTEPS_FULL,
        ),
    };
    let soft_iterations = if default.solver == Solver::SoftStep {
        default.iterations
    } else {
        1
    };
    let mut grid = Vec::new();
    for &backend in backends {
        let mut here: Vec<TumbleSetting> = Vec::new();
        let mut push = |solver, iterations, substeps, warm_start| {
            here.push(TumbleSetting {
                solver,
                iterations,
                substeps,
                warm_start,
                backend,
                is_default: false,
            })
        };
        for (list, warm) in [(b_warm, true), (b_cold, false)] {
            for &it in list {
                push(Solver::Baumgarte, it, 1, warm);
            }
        }
        for (list, warm) in [(s_warm, true), (s_cold, false)] {
            for &ss in list {
                push(Solver::SoftStep, soft_iterations, ss, warm);
            }
        }
        for &ss in relax_friction {
            push(Solver::SoftStepRelaxFriction, soft_iterations, ss, true);
        }
        let default_here = TumbleSetting {
            backend,
            is_default: false,
            ..default
        };
        match here.iter_mut().find(|t| **t == default_here) {
            Some(t) => t.is_default = true,
            None => here.push(TumbleSetting {
                is_default: true,
                ..default_here
            }),
        }
        grid.extend(here.into_iter().map(RunConfig::Tumble));
    }
    grid.extend(
        rapier
            .iter()
            .map(|&substeps| RunConfig::Rapier { substeps }),
    );
    grid
}

#[cfg(test)]
mod tests {
    use super::*;

    fn soft_default() -> TumbleSetting {
        TumbleSetting {
            solver: Solver::SoftStep,
            iterations: 1,
            substeps: 4,
            warm_start: true,
            backend: BackendChoice::Cpu,
            is_default: true,
        }
    }

    #[test]
    fn quick_grid_has_at_least_twelve_tumble_configs_and_rapier() {
        let grid = build_grid(GridSize::Quick, &[BackendChoice::Cpu], soft_default());
        let tumble = grid.iter().filter(|c| c.engine() == "tumble").count();
        let rapier = grid.iter().filter(|c| c.engine() == "rapier3d").count();
        assert!(tumble >= 12, "{tumble}");
        assert!(rapier >= 1);
    }

    #[test]
    fn default_is_marked_exactly_once_per_backend_and_never_duplicated() {
        for size in [GridSize::Quick, GridSize::Full] {
            let backends = [BackendChoice::Cpu, BackendChoice::Gpu];
            let grid = build_grid(size, &backends, soft_default());
            let defaults = grid
                .iter()
                .filter(|c| matches!(c, RunConfig::Tumble(t) if t.is_default))
                .count();
            assert_eq!(defaults, backends.len());
            let mut seen = std::collections::HashSet::new();
            assert!(
                grid.iter().all(|c| seen.insert(*c)),
                "duplicate configuration"
            );
            assert_eq!(grid.iter().filter(|c| c.is_default_cpu()).count(), 1);
        }
    }

    #[test]
    fn an_off_grid_default_is_added() {
        let odd = TumbleSetting {
            iterations: 3,
            substeps: 6,
            ..soft_default()
        };
        let grid = build_grid(GridSize::Quick, &[BackendChoice::Cpu], odd);
        assert!(
            grid.iter()
                .any(|c| matches!(c, RunConfig::Tumble(t) if t.is_default && t.substeps == 6))
        );
    }

    #[test]
    fn full_grid_holds_every_combination() {
        let grid = build_grid(
            GridSize::Full,
            &[BackendChoice::Cpu, BackendChoice::Hybrid],
            soft_default(),
        );
        // Per backend: 9 Baumgarte counts and 5 soft-step counts, each warm and cold, and the
        // 5 soft-step counts with friction in the relax passes only, warm.
        let per_backend = 2 * (BAUMGARTE_ITERATIONS_FULL.len() + SOFT_SUBSTEPS_FULL.len())
            + SOFT_SUBSTEPS_FULL.len();
        assert_eq!(grid.len(), 2 * per_backend + RAPIER_SUBSTEPS_FULL.len());
        assert!(grid.iter().any(|c| c.effort() == 150));
    }

    #[test]
    fn backends_parse_and_reject_unknown_names() {
        assert_eq!(BackendChoice::parse(" GPU "), Ok(BackendChoice::Gpu));
        let err = BackendChoice::parse("tpu").unwrap_err();
        assert!(err.contains("tpu"), "{err}");
    }
}
