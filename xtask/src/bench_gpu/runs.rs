//! Timed runs of one scene on one engine: Tumble's backends through the facade, rapier3d on
//! all cores; warm-up, the run budget, wall time per step with a pose read.

use super::*;

/// Warm-up steps before timing starts (pipelines compile, buffers grow, caches warm up),
/// fewer when the budget of a run says so.
pub(super) const WARMUP_STEPS: usize = 10;
/// The fewest timed steps of a run, whatever its budget.
pub(super) const MIN_TIMED_STEPS: usize = 5;
/// An engine of a row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Engine {
    Tumble(Backend),
    Rapier,
}

impl Engine {
    pub(super) fn parse(name: &str) -> Result<Self, String> {
        match name.trim() {
            "gpu" => Ok(Self::Tumble(Backend::Gpu)),
            "cpu" => Ok(Self::Tumble(Backend::Cpu)),
            "hybrid" => Ok(Self::Tumble(Backend::Hybrid)),
            "rapier" => Ok(Self::Rapier),
            other => Err(format!(
                "unknown backend {other:?}: gpu, rapier, cpu or hybrid"
            )),
        }
    }

    pub(super) fn name(self) -> &'static str {
        match self {
            Self::Tumble(Backend::Gpu) => "tumble-gpu",
            Self::Tumble(Backend::Cpu) => "tumble-cpu",
            Self::Tumble(Backend::Hybrid) => "tumble-hybrid",
            Self::Rapier => "rapier3d",
        }
    }
}

/// The steps of one run: warm-up until [`WARMUP_STEPS`] or a quarter of the budget, then timed
/// steps until `steps` or the budget (at least [`MIN_TIMED_STEPS`]). Returns the timed steps'
/// wall times in ms and a note when the budget cut the run short.
pub(super) fn timed_steps(
    steps: usize,
    budget: Duration,
    mut step: impl FnMut() -> Result<(), String>,
) -> Result<(Vec<f64>, String), String> {
    let start = Instant::now();
    let mut last = Duration::ZERO;
    let mut warm = 0;
    while warm < WARMUP_STEPS && (warm < 2 || start.elapsed() < budget / 4) {
        let t0 = Instant::now();
        step()?;
        last = t0.elapsed();
        warm += 1;
    }
    let left = budget.saturating_sub(start.elapsed());
    let affordable = (left.as_secs_f64() / last.as_secs_f64().max(1e-6)) as usize;
    let timed = steps.min(affordable.max(MIN_TIMED_STEPS)).max(1);
    let mut ms = Vec::with_capacity(timed);
    for _ in 0..timed {
        let t0 = Instant::now();
        step()?;
        ms.push(t0.elapsed().as_secs_f64() * 1e3);
    }
    let note = if timed < steps || warm < WARMUP_STEPS {
        format!("budget: {warm} warm-up + {timed} timed steps")
    } else {
        String::new()
    };
    Ok((ms, note))
}

/// One engine's row on one scene, without the GPU profile.
pub(super) fn run_engine(scene: &Scene, engine: Engine, args: &BenchGpuArgs, steps: usize) -> Row {
    let budget = Duration::from_secs_f64(args.budget_s);
    let outcome = catch_unwind(AssertUnwindSafe(|| match engine {
        Engine::Tumble(backend) => run_tumble(scene, backend, args.substeps, steps, budget),
        Engine::Rapier => Ok(run_rapier(scene, args.substeps, steps, budget)),
    }))
    .unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_owned()))
            .unwrap_or_else(|| "a panic".to_owned());
        Err(format!("panicked: {what}"))
    });
    let mut row = Row::new(&scene.name, scene.bodies.len(), engine.name());
    match outcome {
        Ok(result) => {
            let (drift, lowest) = drift_and_lowest(scene, &result.positions);
            row.set_times(&result.ms);
            row.drift_m = Some(drift);
            row.lowest_m = Some(lowest);
            row.note = result.note;
        }
        Err(e) => row.note = format!("skipped: {e}"),
    }
    row
}

/// What a run measured.
pub(super) struct RunResult {
    pub(super) ms: Vec<f64>,
    pub(super) positions: Vec<[f32; 3]>,
    pub(super) note: String,
}

pub(super) fn run_tumble(
    scene: &Scene,
    backend: Backend,
    substeps: u32,
    steps: usize,
    budget: Duration,
) -> Result<RunResult, String> {
    let config = WorldConfig {
        backend,
        solver: SolverConfig {
            substeps,
            ..SolverConfig::default()
        },
        // Every body awake, as in nexus and in the rapier3d rows.
        effects: tumble::EffectOverrides::NO_SLEEP,
        ..WorldConfig::default()
    };
    let (mut world, handles) = World::from_scene(scene, config).map_err(|e| e.to_string())?;
    let last = *handles.last().ok_or("the scene has no bodies")?;
    // Where a step's wall time goes: the `step` call (recording, submitting, and on GPU
    // backends the last step's motion check) and the pose read that waits for the GPU.
    let mut in_step = Vec::new();
    let (ms, note) = timed_steps(steps, budget, || {
        let t0 = Instant::now();
        world.step().map_err(|e| e.to_string())?;
        in_step.push(t0.elapsed().as_secs_f64() * 1e3);
        // Reading one pose forces the step's results back to the host on GPU backends.
        world.pose(last).map(|_| ()).map_err(|e| e.to_string())
    })?;
    // The timed steps are the last `ms.len()` calls; the split is their medians.
    let first_timed = in_step.len() - ms.len();
    let timed = &mut in_step[first_timed..];
    timed.sort_by(f64::total_cmp);
    let mut whole = ms.clone();
    whole.sort_by(f64::total_cmp);
    let split = format!(
        "step call {:.3} ms, rest (the pose read) {:.3} ms: medians",
        timed[timed.len() / 2],
        whole[whole.len() / 2] - timed[timed.len() / 2]
    );
    let note = [note, split]
        .into_iter()
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join("; ");
    let positions = handles
        .iter()
        .map(|&h| {
            let p = world.pose(h).map_err(|e| e.to_string())?.translation.vector;
            Ok([p.x, p.y, p.z])
        })
        .collect::<Result<Vec<_>, String>>()?;
    Ok(RunResult {
        ms,
        positions,
        note,
    })
}

pub(super) fn run_rapier(
    scene: &Scene,
    substeps: u32,
    steps: usize,
    budget: Duration,
) -> RunResult {
    let options = RapierOptions {
        solver_iterations: substeps as usize,
        ..RapierOptions::default()
    };
    let mut world = build_rapier_with(scene, &options);
    let (ms, note) = timed_steps(steps, budget, || {
        world.step();
        Ok(())
    })
    .expect("rapier3d steps cannot fail");
    let positions = world.body_poses().into_iter().map(|(p, _)| p).collect();
    let threads = rapier_threads();
    RunResult {
        ms,
        positions,
        note: [threads, note]
            .into_iter()
            .filter(|s| !s.is_empty())
            .collect::<Vec<_>>()
            .join("; "),
    }
}

/// How rapier3d runs in this build.
pub(super) fn rapier_threads() -> String {
    if cfg!(feature = "rapier-parallel") {
        format!(
            "parallel, {} threads",
            std::thread::available_parallelism().map_or(1, |n| n.get())
        )
    } else {
        "one thread (built without the rapier-parallel feature)".to_owned()
    }
}
