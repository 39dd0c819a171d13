//! The report folder: `results.csv`, one plot per scene (PNG and SVG), and `report.md`.

use std::fmt::Write as _;
use std::path::Path;

use tumble::scenes::Scene;

use crate::backends::BackendPlan;
use crate::grid::{BackendChoice, GridSize, RunConfig, Solver};
use crate::last_frames::LastFrames;
use crate::plot::{PlotPoint, plot_scene};
use crate::results::{ResultRow, STAGES, csv_header, csv_line};
use crate::scene_set::file_stem;
use crate::table;

/// What the report says about the run besides its rows.
pub struct ReportContext<'a> {
    /// Quick or full.
    pub size: GridSize,
    /// The scenes, in run order.
    pub scenes: &'a [Scene],
    /// Backends run and skipped.
    pub plan: &'a BackendPlan,
    /// Configurations per scene.
    pub grid_len: usize,
    /// Wall time of the whole validation, in seconds.
    pub elapsed_s: f64,
    /// Step cap of quick grid points.
    pub quick_max_steps: u32,
    /// The last frame of each scene's verdict run, beside the report.
    pub frames: &'a LastFrames,
}

/// The plotted points of one scene: grid runs that finished without error.
pub fn plot_points(rows: &[ResultRow], scene: &str) -> Vec<PlotPoint> {
    rows.iter()
        .filter(|r| r.scene == scene && r.in_grid && r.outcome.error.is_none())
        .map(|r| PlotPoint {
            tumble: match &r.config {
                RunConfig::Tumble(t) => Some((t.solver, t.backend, t.warm_start)),
                RunConfig::Rapier { .. } => None,
            },
            effort: r.config.effort(),
            ms_per_step: r.outcome.timing.median_ms,
            max_penetration: f64::from(r.outcome.metrics.max_penetration),
            max_drift: f64::from(r.outcome.metrics.max_drift),
        })
        .collect()
}

/// Writes the whole report folder.
pub fn write_report(dir: &Path, ctx: &ReportContext<'_>, rows: &[ResultRow]) -> Result<(), String> {
    let plots = dir.join("plots");
    std::fs::create_dir_all(&plots).map_err(|e| format!("--out {}: {e}", dir.display()))?;
    let write = |name: &str, text: &str| {
        std::fs::write(dir.join(name), text)
            .map_err(|e| format!("writing {}: {e}", dir.join(name).display()))
    };

    let mut csv = csv_header();
    csv.push('\n');
    for row in rows {
        csv.push_str(&csv_line(row));
        csv.push('\n');
    }
    write("results.csv", &csv)?;

    for scene in ctx.scenes {
        let points = plot_points(rows, &scene.name);
        if !points.is_empty() {
            plot_scene(&plots, &file_stem(&scene.name), &scene.name, &points)?;
        }
    }
    write("report.md", &markdown(ctx, rows))
}

fn markdown(ctx: &ReportContext<'_>, rows: &[ResultRow]) -> String {
    let mut md = String::new();
    let size = match ctx.size {
        GridSize::Quick => format!(
            "quick (grid points capped at {} steps; the default configuration's verdict run covers each scene's full length)",
            ctx.quick_max_steps
        ),
        GridSize::Full => "full (every grid point runs each scene's full length)".into(),
    };
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let _ = writeln!(md, "# Tumble validation report\n");
    let _ = writeln!(
        md,
        "Produced by `cargo xtask validate`. Metric definitions and how to read the plots: `docs/validation.md`.\n"
    );
    let _ = writeln!(md, "- grid: {size}");
    let _ = writeln!(
        md,
        "- {} scenes x {} configurations, {} runs, {:.0} s wall time",
        ctx.scenes.len(),
        ctx.grid_len,
        rows.len(),
        ctx.elapsed_s
    );
    let _ = writeln!(
        md,
        "- machine: {cores} logical CPUs, {} {}",
        std::env::consts::OS,
        std::env::consts::ARCH
    );
    let run: Vec<&str> = ctx.plan.run.iter().map(|b| b.name()).collect();
    let _ = writeln!(md, "- backends run: {}", run.join(", "));
    if let Some(adapter) = &ctx.plan.adapter {
        let _ = writeln!(md, "- GPU adapter: {adapter}");
    }
    for (b, why) in &ctx.plan.skipped {
        let _ = writeln!(md, "- **SKIPPED backend `{}`**: {why}", b.name());
    }
    if let Some(adapter) = &ctx.frames.adapter {
        let _ = writeln!(
            md,
            "- last frames: each scene's verdict run at its last step, drawn by tumble-render on {adapter}"
        );
    }
    for note in &ctx.frames.notes {
        let _ = writeln!(md, "- **last frames**: {note}");
    }

    let _ = writeln!(
        md,
        "\n## Verdicts (default configuration, CPU, full length)\n"
    );
    let _ = writeln!(
        md,
        "| scene | check | measured | limit | result |\n|---|---|---:|---:|---|"
    );
    for r in rows.iter().filter(|r| r.verdict_run) {
        match (&r.check, &r.outcome.error) {
            (_, Some(e)) => {
                let _ = writeln!(md, "| {} | - | - | - | **ERROR** {e} |", r.scene);
            }
            (Some(c), None) => {
                let verdict = if c.passed { "pass" } else { "**FAIL**" };
                let _ = writeln!(
                    md,
                    "| {} | {} | {:.4} | {} | {verdict} |",
                    r.scene, c.check, c.measured, c.limit
                );
            }
            (None, None) => {
                let _ = writeln!(md, "| {} | - | - | - | - |", r.scene);
            }
        }
    }

    md.push_str(&thesis_table(ctx, rows));

    for scene in ctx.scenes {
        let _ = writeln!(md, "\n## {}\n", scene.name);
        if !scene.description.is_empty() {
            let _ = writeln!(md, "{}\n", scene.description);
        }
        let _ = writeln!(
            md,
            "{} bodies ({} dynamic), {} steps of {:.4} s.\n",
            scene.bodies.len(),
            scene.dynamic_count(),
            scene.steps,
            scene.dt
        );
        if let Some(stages) = stage_line(rows, &scene.name) {
            let _ = writeln!(md, "{stages}\n");
        }
        let stem = file_stem(&scene.name);
        if let Some(frame) = ctx.frames.frame_of(&scene.name) {
            let _ = writeln!(md, "![{}, last frame]({frame})\n", scene.name);
        }
        let _ = writeln!(md, "![{}](plots/{stem}.png)\n", scene.name);
        let cells: Vec<Vec<String>> = rows
            .iter()
            .filter(|r| r.scene == scene.name)
            .map(table::cells)
            .collect();
        md.push_str(&table::markdown(&cells));
    }
    md
}

/// "Median stage times of the default configuration: ..." for one scene, when measured.
fn stage_line(rows: &[ResultRow], scene: &str) -> Option<String> {
    let row = rows
        .iter()
        .find(|r| r.scene == scene && r.in_grid && r.config.is_default_cpu())?;
    if row.outcome.stage_ms.is_empty() {
        return None;
    }
    let parts: Vec<String> = STAGES
        .iter()
        .filter_map(|s| {
            row.outcome
                .stage_ms
                .get(*s)
                .map(|ms| format!("{s} {ms:.3}"))
        })
        .collect();
    Some(format!(
        "Median stage times of the default configuration on the CPU, ms: {}.",
        parts.join(", ")
    ))
}

/// The thesis's three settings and the CPU references they are compared with.
const THESIS_SETTINGS: [(&str, BackendChoice, Solver, Option<u32>); 5] = [
    (
        "thesis: CPU solver, 150 iterations, GPU collision",
        BackendChoice::Hybrid,
        Solver::Baumgarte,
        Some(150),
    ),
    (
        "thesis: whole step on the GPU, 5 iterations",
        BackendChoice::Gpu,
        Solver::Baumgarte,
        Some(5),
    ),
    (
        "colored GPU solver, default settings",
        BackendChoice::Gpu,
        Solver::SoftStep,
        None,
    ),
    (
        "reference: CPU, Baumgarte 150 iterations",
        BackendChoice::Cpu,
        Solver::Baumgarte,
        Some(150),
    ),
    (
        "reference: CPU, default settings",
        BackendChoice::Cpu,
        Solver::SoftStep,
        None,
    ),
];

/// Whether `config` is the thesis table's setting: Baumgarte runs are the cold ones (the
/// thesis had no warm starting); `None` iterations means the default configuration.
fn is_setting(
    config: &RunConfig,
    backend: BackendChoice,
    solver: Solver,
    iterations: Option<u32>,
) -> bool {
    match config {
        RunConfig::Tumble(t) => {
            t.backend == backend
                && t.solver == solver
                && match iterations {
                    Some(n) => t.iterations == n && t.substeps == 1 && !t.warm_start,
                    None => t.is_default,
                }
        }
        RunConfig::Rapier { .. } => false,
    }
}

/// The thesis's results table, remeasured: steps per second and whether the scene holds, on
/// simple stacking (the column), a pool of boxes and extreme stacking (the largest pyramid).
fn thesis_table(ctx: &ReportContext<'_>, rows: &[ResultRow]) -> String {
    let pick = |prefix: &str| -> Option<&str> {
        ctx.scenes
            .iter()
            .filter(|s| s.name.starts_with(prefix))
            .max_by_key(|s| s.bodies.len())
            .map(|s| s.name.as_str())
    };
    let scenes: Vec<&str> = ["stack", "pool", "pyramid"]
        .iter()
        .filter_map(|p| pick(p))
        .collect();
    if scenes.is_empty() {
        return String::new();
    }
    let mut md = String::from("\n## The thesis's settings, remeasured\n\n");
    md.push_str(
        "Steps per second (1000 / median ms per step) and the scene's check over the grid run \
         (in a quick run, the shortened run). The thesis reported about 2,500 steps/s for its CPU \
         solver at 150 iterations with GPU collision, and 30 to 60 for its whole-GPU step at 5 \
         iterations, on an RTX 3070 and a Ryzen 5600X.\n\n",
    );
    let _ = writeln!(md, "| setting | {} |", scenes.join(" | "));
    let _ = writeln!(md, "|---|{}", "---:|".repeat(scenes.len()));
    for (label, backend, solver, iterations) in THESIS_SETTINGS {
        let cells: Vec<String> = scenes
            .iter()
            .map(|scene| {
                rows.iter()
                    .find(|r| {
                        r.scene == *scene
                            && r.in_grid
                            && is_setting(&r.config, backend, solver, iterations)
                    })
                    .map_or("not run".into(), |r| {
                        let holds = match r.passed() {
                            Some(true) => "holds",
                            Some(false) => "fails",
                            None => "-",
                        };
                        format!("{:.0} steps/s, {holds}", r.steps_per_second())
                    })
            })
            .collect();
        let _ = writeln!(md, "| {label} | {} |", cells.join(" | "));
    }
    md
}
