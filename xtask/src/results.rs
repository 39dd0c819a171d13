//! One row of results per scene x configuration, and its CSV form.

use std::fmt::Write as _;

use tumble::scenes::CheckReport;

use crate::grid::RunConfig;
use crate::run::RunOutcome;

/// Tumble's stage names, in step order: the per-stage CSV columns.
pub const STAGES: [&str; 6] = [
    "update_aabbs",
    "broad_phase",
    "narrow_phase",
    "color",
    "solve",
    "finish",
];

/// The result of running one configuration on one scene.
#[derive(Clone, Debug)]
pub struct ResultRow {
    /// The scene's name.
    pub scene: String,
    /// The engine configuration.
    pub config: RunConfig,
    /// True for the full-length run of the default configuration whose check decides the
    /// exit code.
    pub verdict_run: bool,
    /// True for grid points (plotted); false for the extra full-length verdict run of a quick
    /// validation, whose length differs from its neighbours'.
    pub in_grid: bool,
    /// Time step of the scene, in seconds.
    pub dt: f32,
    /// Metrics and timings.
    pub outcome: RunOutcome,
    /// The scene's pass check over this run (`None` when the engine could not be built).
    pub check: Option<CheckReport>,
}

impl ResultRow {
    /// Whether the run passed its scene's check: `Some(false)` for a failed check or an
    /// engine error, `None` when there was nothing to judge.
    pub fn passed(&self) -> Option<bool> {
        if self.outcome.error.is_some() {
            return Some(false);
        }
        self.check.as_ref().map(|c| c.passed)
    }

    /// Steps per second of simulation work (1000 / median ms).
    pub fn steps_per_second(&self) -> f64 {
        let ms = self.outcome.timing.median_ms;
        if ms > 0.0 { 1e3 / ms } else { f64::INFINITY }
    }
}

/// Header of `results.csv`.
pub fn csv_header() -> String {
    let mut cols: Vec<String> = [
        "scene",
        "engine",
        "series",
        "solver",
        "backend",
        "iterations",
        "substeps",
        "warm_start",
        "is_default",
        "verdict_run",
        "in_grid",
        "steps",
        "dt_s",
        "ms_per_step_median",
        "ms_per_step_mean",
        "ms_per_step_max",
        "steps_per_s",
        "max_penetration_m",
        "mean_penetration_m",
        "engine_max_penetration_m",
        "max_drift_m",
        "jitter_rms_mps",
        "energy_drift_rel",
        "energy_gain_max_rel",
        "time_to_rest_s",
        "nan_bodies",
        "check",
        "check_measured",
        "check_limit",
        "pass",
        "error",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    cols.extend(STAGES.iter().map(|s| format!("ms_{s}_median")));
    cols.join(",")
}

/// Quotes a CSV field when it holds a comma, a quote or a line break.
pub fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

fn opt<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map_or(String::new(), |v| v.to_string())
}

/// One `results.csv` line (no trailing newline).
pub fn csv_line(row: &ResultRow) -> String {
    let m = &row.outcome.metrics;
    let t = &row.outcome.timing;
    let (solver, backend, iterations, substeps, warm, default) = match &row.config {
        RunConfig::Tumble(s) => (
            s.solver.name().to_string(),
            s.backend.name().to_string(),
            s.iterations.to_string(),
            s.substeps.to_string(),
            s.warm_start.to_string(),
            s.is_default.to_string(),
        ),
        RunConfig::Rapier { substeps } => (
            "rapier_tgs_soft".into(),
            "cpu".into(),
            "1".into(),
            substeps.to_string(),
            "true".into(),
            "false".into(),
        ),
    };
    let mut line = String::new();
    let fields: Vec<String> = vec![
        csv_field(&row.scene),
        row.config.engine().into(),
        csv_field(&row.config.series()),
        solver,
        backend,
        iterations,
        substeps,
        warm,
        default,
        row.verdict_run.to_string(),
        row.in_grid.to_string(),
        m.steps.to_string(),
        format!("{}", row.dt),
        format!("{:.6}", t.median_ms),
        format!("{:.6}", t.mean_ms),
        format!("{:.6}", t.max_ms),
        format!("{:.2}", row.steps_per_second()),
        format!("{:.7}", m.max_penetration),
        format!("{:.7}", m.mean_penetration),
        opt(row
            .outcome
            .reported_max_penetration
            .map(|p| format!("{p:.7}"))),
        format!("{:.7}", m.max_drift),
        opt(m.jitter_rms.map(|j| format!("{j:.7}"))),
        opt(m.energy_drift.map(|e| format!("{e:.7}"))),
        opt(m.energy_gain_max.map(|e| format!("{e:.7}"))),
        opt(m.time_to_rest.map(|t| format!("{t:.4}"))),
        m.nan_bodies.to_string(),
        opt(row.check.as_ref().map(|c| c.check)),
        opt(row.check.as_ref().map(|c| c.measured)),
        opt(row.check.as_ref().map(|c| c.limit)),
        opt(row.passed().map(|p| if p { "pass" } else { "FAIL" })),
        csv_field(row.outcome.error.as_deref().unwrap_or("")),
    ];
    line.push_str(&fields.join(","));
    for stage in STAGES {
        let _ = write!(
            line,
            ",{}",
            opt(row.outcome.stage_ms.get(stage).map(|v| format!("{v:.6}")))
        );
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::RunMetrics;

    #[test]
    fn every_line_has_as_many_fields_as_the_header() {
        let row = ResultRow {
            scene: "ramp, 30deg".into(),
            config: RunConfig::Rapier { substeps: 4 },
            verdict_run: false,
            in_grid: true,
            dt: 1.0 / 60.0,
            outcome: RunOutcome {
                metrics: RunMetrics {
                    steps: 10,
                    ..Default::default()
                },
                error: Some("said \"no\"".into()),
                ..Default::default()
            },
            check: None,
        };
        let line = csv_line(&row);
        // Count fields outside quotes.
        let mut fields = 1;
        let mut quoted = false;
        for c in line.chars() {
            match c {
                '"' => quoted = !quoted,
                ',' if !quoted => fields += 1,
                _ => {}
            }
        }
        assert_eq!(fields, csv_header().split(',').count());
        assert!(line.starts_with("\"ramp, 30deg\",rapier3d,"));
        assert!(line.contains("\"said \"\"no\"\"\""));
        // An engine error fails the run even without a check.
        assert_eq!(row.passed(), Some(false));
    }
}
