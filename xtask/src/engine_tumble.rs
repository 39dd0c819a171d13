//! Tumble behind the `Engine` trait: a `World` built from the scene with one solver setting.

use std::time::Duration;

use tumble::scenes::Scene;
use tumble::{
    Backend, BodyHandle, EffectOverrides, FrictionPasses, SolverConfig, SolverKind, World,
    WorldConfig,
};

use crate::engine::{BodyState, Engine, StageTime};
use crate::grid::{BackendChoice, Solver, TumbleSetting};

/// A Tumble world loaded with a scene.
pub struct TumbleEngine {
    world: World,
    handles: Vec<BodyHandle>,
}

/// The facade's backend for a grid backend.
pub fn backend(choice: BackendChoice) -> Backend {
    match choice {
        BackendChoice::Cpu => Backend::Cpu,
        BackendChoice::Gpu => Backend::Gpu,
        BackendChoice::Hybrid => Backend::Hybrid,
    }
}

/// The solver configuration of a grid point: the library's defaults for that solver with the
/// grid's iteration, substep and warm-start values on top, so every other tuning constant is
/// the one users get.
pub fn solver_config(setting: &TumbleSetting) -> SolverConfig {
    let base = match setting.solver {
        Solver::Baumgarte => SolverConfig::baumgarte(),
        Solver::SoftStep => SolverConfig::soft_step(),
        Solver::SoftStepRelaxFriction => SolverConfig {
            friction_passes: FrictionPasses::RelaxOnly,
            ..SolverConfig::soft_step()
        },
    };
    SolverConfig {
        iterations: setting.iterations,
        substeps: setting.substeps,
        warm_start: setting.warm_start,
        ..base
    }
}

/// The grid point `SolverConfig::default()` corresponds to, on the CPU.
pub fn default_setting() -> TumbleSetting {
    let d = SolverConfig::default();
    TumbleSetting {
        solver: match d.kind {
            SolverKind::Baumgarte => Solver::Baumgarte,
            SolverKind::SoftStep => Solver::SoftStep,
        },
        iterations: d.iterations,
        substeps: d.substeps,
        warm_start: d.warm_start,
        backend: BackendChoice::Cpu,
        is_default: true,
    }
}

/// Whether `choice` can run here: `Err` carries the facade's reason (no adapter, say).
pub fn probe_backend(choice: BackendChoice) -> Result<(), String> {
    World::new(WorldConfig {
        backend: backend(choice),
        ..Default::default()
    })
    .map(|_| ())
    .map_err(|e| e.to_string())
}

impl TumbleEngine {
    /// Builds `scene` with `setting`.
    pub fn new(scene: &Scene, setting: &TumbleSetting) -> Result<Self, String> {
        let config = WorldConfig {
            solver: solver_config(setting),
            backend: backend(setting.backend),
            // Drift and cost of the solver itself: no body is put to sleep (nor is any of
            // rapier's, see engine_rapier).
            effects: EffectOverrides::NO_SLEEP,
            ..Default::default()
        };
        let (world, handles) = World::from_scene(scene, config).map_err(|e| e.to_string())?;
        Ok(Self { world, handles })
    }
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

impl Engine for TumbleEngine {
    fn step(&mut self) -> Result<(), String> {
        self.world.step().map_err(|e| e.to_string())
    }

    fn read_states(&self, out: &mut Vec<BodyState>) {
        out.clear();
        for &h in &self.handles {
            // Handles come from `from_scene` and are never removed, so the lookups succeed;
            // a failure would be a facade bug, reported as a NaN body rather than a panic.
            let nan = tumble::Vec3::repeat(f32::NAN);
            out.push(BodyState {
                pose: self.world.pose(h).unwrap_or_else(|_| {
                    let mut p = tumble::Pose::identity();
                    p.translation.vector = nan;
                    p
                }),
                linear_velocity: self.world.linear_velocity(h).unwrap_or(nan),
                angular_velocity: self.world.angular_velocity(h).unwrap_or(nan),
            });
        }
    }

    fn stage_times(&self) -> Vec<StageTime> {
        let t = &self.world.stats().timings;
        [
            ("update_aabbs", t.update_aabbs),
            ("broad_phase", t.broad_phase),
            ("narrow_phase", t.narrow_phase),
            ("color", t.color),
            ("solve", t.solve),
            ("finish", t.finish),
        ]
        .into_iter()
        .map(|(name, d)| StageTime {
            name: name.into(),
            ms: ms(d),
        })
        .collect()
    }

    fn reported_max_penetration(&self) -> Option<f32> {
        Some(self.world.max_penetration())
    }
}
