//! The report folder: `results.csv`, one plot per scene (PNG and SVG), and `report.md`.

use std::fmt::Write as _;
use std::path::Path;

use tumble::scenes::Scene;

use crate::backends::BackendPlan;
use crate::grid::GridSize;
use crate::plot::{PlotPoint, plot_scene};
use crate::results::{ResultRow, csv_header, csv_line};
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
}

/// The plotted points of one scene: grid runs that finished without error.
pub fn plot_points(rows: &[ResultRow], scene: &str) -> Vec<PlotPoint> {
    rows.iter()
        .filter(|r| r.scene == scene && r.in_grid && r.outcome.error.is_none())
        .map(|r| PlotPoint {
            series: r.config.series(),
            is_rapier: r.config.engine() == "rapier3d",
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
        let stem = file_stem(&scene.name);
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
