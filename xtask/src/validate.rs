//! `cargo xtask validate`: every scene under every configuration, measured, tabled, plotted.

use std::path::PathBuf;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use tumble::scenes::{BodyState as SceneState, CheckTracker, Scene};

use crate::backends::{BackendPlan, plan_backends};
use crate::batch::{Done, run_batches};
use crate::engine::{BodyState, Engine};
use crate::engine_rapier::RapierEngine;
use crate::engine_tumble::{TumbleEngine, default_setting};
use crate::grid::{BackendChoice, GridSize, RunConfig, build_grid};
use crate::last_frames::draw_last_frames;
use crate::report::{ReportContext, write_report};
use crate::results::ResultRow;
use crate::run::{RunOutcome, run_engine};
use crate::scene_set::{
    filter_scenes, full_scenes, load_scene_files, quick_scenes, scene_info, should_rest,
};
use crate::table;

/// Step cap of a quick run's grid points: 3 s at 60 Hz, enough for stacks to show creep and
/// for the 1 s jitter window to start after the first contacts settle. The default
/// configuration's verdict run always covers the scene's full length.
pub const QUICK_MAX_STEPS: u32 = 180;

/// What `cargo xtask validate` was asked to do.
#[derive(Clone, Debug)]
pub struct ValidateArgs {
    /// Quick or full grid.
    pub size: GridSize,
    /// Scene files; empty for the built-in set.
    pub scene_files: Vec<PathBuf>,
    /// Report folder.
    pub out: PathBuf,
    /// `--backends`, `None` for every backend with hardware here.
    pub backends: Option<Vec<BackendChoice>>,
    /// `--filter`: keep scenes whose name contains this.
    pub filter: Option<String>,
    /// `--batch`: run each scene's Tumble grid again as batches and compare.
    pub batch: bool,
}

/// One unit of work: a configuration on a scene for some steps.
struct Job {
    scene: usize,
    config: RunConfig,
    steps: u32,
    verdict_run: bool,
    in_grid: bool,
}

/// Converts a measured state into the scene crate's plain-array state for its check.
fn to_scene_state(s: &BodyState) -> SceneState {
    let t = s.pose.translation.vector;
    let q = s.pose.rotation.coords;
    SceneState {
        position: [t.x, t.y, t.z],
        rotation: [q.x, q.y, q.z, q.w],
        linear_velocity: s.linear_velocity.into(),
        angular_velocity: s.angular_velocity.into(),
    }
}

/// Runs one job and judges it with the scene's check; `last` ends with the states after the
/// last step (empty when the engine could not be built).
fn run_job(scene: &Scene, job: &Job, last: &mut Vec<BodyState>) -> ResultRow {
    last.clear();
    let info = scene_info(scene);
    let built: Result<Box<dyn Engine>, String> = match &job.config {
        RunConfig::Tumble(setting) => {
            TumbleEngine::new(scene, setting).map(|e| Box::new(e) as Box<dyn Engine>)
        }
        RunConfig::Rapier { substeps } => Ok(Box::new(RapierEngine::new(scene, *substeps))),
    };
    let (outcome, check) = match built {
        Ok(mut engine) => {
            let mut tracker = CheckTracker::new(scene);
            let mut scratch = Vec::with_capacity(scene.bodies.len());
            let outcome = run_engine(
                engine.as_mut(),
                &info,
                should_rest(scene),
                job.steps as usize,
                &mut |states| {
                    scratch.clear();
                    scratch.extend(states.iter().map(to_scene_state));
                    last.clear();
                    last.extend_from_slice(states);
                    // The lengths always match (one state per scene body), so this cannot fail.
                    let _ = tracker.observe(&scratch);
                },
            );
            (outcome, Some(tracker.finish()))
        }
        Err(e) => (
            RunOutcome {
                error: Some(e),
                ..Default::default()
            },
            None,
        ),
    };
    ResultRow {
        scene: scene.name.clone(),
        config: job.config,
        verdict_run: job.verdict_run,
        in_grid: job.in_grid,
        dt: scene.dt,
        outcome,
        check,
    }
}

/// Lays out the jobs: per scene, the verdict run (quick only: in a full run the default
/// configuration's own grid point is full length and serves), then the grid.
fn plan_jobs(scenes: &[Scene], grid: &[RunConfig], size: GridSize) -> Vec<Job> {
    let mut jobs = Vec::new();
    for (i, scene) in scenes.iter().enumerate() {
        let short = match size {
            GridSize::Quick => scene.steps.min(QUICK_MAX_STEPS),
            GridSize::Full => scene.steps,
        };
        for config in grid {
            let verdict = config.is_default_cpu();
            if verdict && size == GridSize::Quick && short < scene.steps {
                jobs.push(Job {
                    scene: i,
                    config: *config,
                    steps: scene.steps,
                    verdict_run: true,
                    in_grid: false,
                });
            }
            jobs.push(Job {
                scene: i,
                config: *config,
                steps: short,
                verdict_run: verdict && short == scene.steps,
                in_grid: true,
            });
        }
    }
    jobs
}

/// Runs the validation; `Ok(true)` when every scene passes its check in the default
/// configuration on the CPU.
pub fn validate(args: &ValidateArgs) -> Result<bool, String> {
    let started = Instant::now();
    // A filter searches every built-in scene, so that `--filter pyramid_24` runs the large
    // pyramid on the quick grid; without one a quick run leaves the large scenes out.
    let scenes = if !args.scene_files.is_empty() {
        load_scene_files(&args.scene_files)?
    } else if args.filter.is_some() || args.size == GridSize::Full {
        full_scenes()
    } else {
        quick_scenes()
    };
    let scenes = filter_scenes(scenes, args.filter.as_deref());
    if scenes.is_empty() {
        return Err(format!(
            "--filter {:?}: no scene matches",
            args.filter.as_deref().unwrap_or("")
        ));
    }

    let plan: BackendPlan = plan_backends(args.backends.as_deref());
    for (b, why) in &plan.skipped {
        eprintln!("SKIPPED backend {}: {why}", b.name());
    }
    let grid = build_grid(args.size, &plan.run, default_setting());
    let jobs = plan_jobs(&scenes, &grid, args.size);

    let bar = ProgressBar::new(jobs.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} {msg}")
            .map_err(|e| e.to_string())?
            .progress_chars("=> "),
    );
    let mut rows = Vec::with_capacity(jobs.len());
    // The verdict runs' final states, for the report's last frame of each scene.
    let mut finals = Vec::new();
    let mut last = Vec::new();
    // With --batch: every Tumble grid run's wall time and final states.
    let mut done = Vec::new();
    for job in &jobs {
        let scene = &scenes[job.scene];
        bar.set_message(format!("{} / {}", scene.name, job.config));
        let t0 = Instant::now();
        rows.push(run_job(scene, job, &mut last));
        if args.batch && job.in_grid && !last.is_empty() {
            let wall = t0.elapsed().as_secs_f64();
            done.extend(Done::of(job.scene, &job.config, job.steps, wall, &last));
        }
        if job.verdict_run && !last.is_empty() {
            finals.push((scene.name.clone(), std::mem::take(&mut last)));
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let frames = draw_last_frames(&args.out, &scenes, &finals);
    for note in &frames.notes {
        eprintln!("{note}");
    }

    for scene in &scenes {
        let cells: Vec<Vec<String>> = rows
            .iter()
            .filter(|r| r.scene == scene.name)
            .map(table::cells)
            .collect();
        println!(
            "\n== {} ({} bodies, {} steps at {:.4} s) ==",
            scene.name,
            scene.bodies.len(),
            scene.steps,
            scene.dt
        );
        print!("{}", table::aligned(&cells));
    }

    let verdicts: Vec<&ResultRow> = rows.iter().filter(|r| r.verdict_run).collect();
    let all_pass = verdicts.iter().all(|r| r.passed() == Some(true));
    let context = ReportContext {
        size: args.size,
        scenes: &scenes,
        plan: &plan,
        grid_len: grid.len(),
        elapsed_s: started.elapsed().as_secs_f64(),
        quick_max_steps: QUICK_MAX_STEPS,
        frames: &frames,
    };
    write_report(&args.out, &context, &rows)?;
    let mut batches_equal = true;
    if args.batch {
        println!("\n== the grid's Tumble runs again, one batch per scene and backend ==");
        let (md, equal) = run_batches(&scenes, &done);
        batches_equal = equal;
        print!("{md}");
        let path = args.out.join("batch.md");
        std::fs::write(&path, format!("# validate --batch\n\n{md}"))
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    println!();
    for r in &verdicts {
        let verdict = match r.passed() {
            Some(true) => "pass",
            _ => "FAIL",
        };
        println!(
            "{verdict:4}  {:<28} default {}",
            r.scene,
            r.check.as_ref().map_or_else(
                || r.outcome.error.clone().unwrap_or_default(),
                |c| c.detail.clone(),
            )
        );
    }
    println!(
        "\n{} runs in {:.0} s; report in {}",
        rows.len(),
        started.elapsed().as_secs_f64(),
        args.out.join("report.md").display()
    );
    Ok(all_pass && batches_equal)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Solver;
    use tumble::scenes;

    #[test]
    fn quick_jobs_add_one_full_length_verdict_per_scene() {
        let scenes = vec![scenes::stack(3), scenes::mass_ratio()];
        let grid = build_grid(GridSize::Quick, &[BackendChoice::Cpu], default_setting());
        let jobs = plan_jobs(&scenes, &grid, GridSize::Quick);
        assert_eq!(jobs.len(), scenes.len() * (grid.len() + 1));
        for (i, scene) in scenes.iter().enumerate() {
            let verdicts: Vec<&Job> = jobs
                .iter()
                .filter(|j| j.scene == i && j.verdict_run)
                .collect();
            assert_eq!(verdicts.len(), 1);
            assert_eq!(verdicts[0].steps, scene.steps);
            assert!(
                jobs.iter()
                    .filter(|j| j.scene == i && !j.verdict_run)
                    .all(|j| j.steps <= QUICK_MAX_STEPS)
            );
        }
    }

    #[test]
    fn a_short_stack_stands_in_tumble_and_rapier_and_is_judged() {
        // A 3-cube column for 1 s: every engine here holds it within its check's 1 cm.
        let mut scene = scenes::stack(3);
        scene.steps = 60;
        let tumble = run_job(
            &scene,
            &Job {
                scene: 0,
                config: RunConfig::Tumble(default_setting()),
                steps: 60,
                verdict_run: true,
                in_grid: true,
            },
            &mut Vec::new(),
        );
        assert_eq!(tumble.passed(), Some(true), "{:?}", tumble.check);
        assert_eq!(tumble.outcome.metrics.steps, 60);
        assert!(tumble.outcome.stage_ms.contains_key("solve"));
        // Resting cubes overlap by at most the solvers' few-millimetre slop; 1 cm would be a
        // visibly sunken stack.
        assert!(tumble.outcome.metrics.max_penetration < 0.01);
        let rapier = run_job(
            &scene,
            &Job {
                scene: 0,
                config: RunConfig::Rapier { substeps: 4 },
                steps: 60,
                verdict_run: false,
                in_grid: true,
            },
            &mut Vec::new(),
        );
        assert_eq!(rapier.passed(), Some(true), "{:?}", rapier.check);
        assert!(rapier.outcome.metrics.max_penetration < 0.01);
        assert_eq!(default_setting().solver, Solver::SoftStep);
    }
}
