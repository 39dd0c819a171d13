//! `bench-gpu`'s rows and outputs: the CSV (shared with `benches/peers/nexus_scenes.py`), the
//! markdown table, the per-pass table and the log-log plot. The traffic model behind the
//! "bytes per step" column is in [`traffic`].

mod csv_file;
mod plot;
mod table;
mod traffic;

use std::fmt::Write as _;
use std::path::Path;

use plotters::prelude::*;
use tumble_gpu::layout::{GpuAabb, GpuContact, GpuManifold, GpuPose, GpuShape, GpuVelocity};
use tumble_gpu::solver::layout::{GpuConstraint, GpuSolverBody};

use crate::fonts::{PLOT_FONT, register_plot_font};

pub use csv_file::*;
use plot::*;
pub use table::*;
pub use traffic::*;

/// The CSV columns, in order (`benches/peers/nexus_scenes.py` writes the same).
pub const CSV_COLUMNS: &[&str] = &[
    "scene",
    "bodies",
    "engine",
    "steps",
    "median_ms",
    "p90_ms",
    "drift_m",
    "lowest_m",
    "gpu_ms",
    "bytes_per_step",
    "floor_ms",
    "x_floor",
    "mem_bytes_per_body",
    "manifolds",
    "note",
];

/// One engine on one scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Row {
    /// The scene's name (as in its JSON file).
    pub scene: String,
    /// Bodies, fixed ones included.
    pub bodies: usize,
    /// `tumble-gpu`, `tumble-cpu`, `tumble-hybrid`, `rapier3d` or `nexus`.
    pub engine: String,
    /// Timed steps.
    pub steps: usize,
    /// Median wall time per step, ms.
    pub median_ms: Option<f64>,
    /// 90th percentile of the wall time per step, ms.
    pub p90_ms: Option<f64>,
    /// Largest horizontal displacement of a dynamic body at the end, m.
    pub drift_m: Option<f64>,
    /// Lowest dynamic body's centre along the up axis at the end, m.
    pub lowest_m: Option<f64>,
    /// Sum of the per-pass GPU times of a step (timestamps), ms.
    pub gpu_ms: Option<f64>,
    /// Bytes moved per step by the traffic model.
    pub bytes_per_step: Option<u64>,
    /// `bytes_per_step / bandwidth`, ms.
    pub floor_ms: Option<f64>,
    /// The GPU time (or, without timestamps, the wall time) over the floor time.
    pub x_floor: Option<f64>,
    /// Device buffer bytes of the world per body.
    pub mem_bytes_per_body: Option<f64>,
    /// Manifolds with contact points at the end of the profiled steps.
    pub manifolds: Option<u64>,
    /// How the row ran, or why it did not.
    pub note: String,
}

impl Row {
    /// An empty row of `engine` on `scene`.
    pub fn new(scene: &str, bodies: usize, engine: &str) -> Self {
        Self {
            scene: scene.to_owned(),
            bodies,
            engine: engine.to_owned(),
            ..Default::default()
        }
    }

    /// Sets the step count, median and 90th percentile from per-step times in ms.
    pub fn set_times(&mut self, ms: &[f64]) {
        let mut sorted = ms.to_vec();
        sorted.sort_by(f64::total_cmp);
        self.steps = sorted.len();
        self.median_ms = Some(crate::timing::median(&sorted));
        self.p90_ms = percentile(&sorted, 0.9);
    }

    /// Fills the floor time and the ratio to it from the bytes per step.
    pub fn fill_floor(&mut self, bandwidth_gbs: f64) {
        if let Some(bytes) = self.bytes_per_step {
            let floor = bytes as f64 / (bandwidth_gbs * 1e9) * 1e3;
            self.floor_ms = Some(floor);
            self.x_floor = self.gpu_ms.or(self.median_ms).map(|t| t / floor);
        }
    }

    /// One line for the console.
    pub fn summary(&self) -> String {
        match self.median_ms {
            None => self.note.clone(),
            Some(median) => {
                let mut s = format!(
                    "median {median:.3} ms, p90 {} ms, {} steps, drift {} mm, lowest {} m",
                    fmt(self.p90_ms, 3),
                    self.steps,
                    fmt(self.drift_m.map(|d| d * 1e3), 2),
                    fmt(self.lowest_m, 3)
                );
                if let Some(gpu) = self.gpu_ms {
                    let _ = write!(s, ", GPU {gpu:.3} ms");
                }
                if let Some(x) = self.x_floor {
                    let _ = write!(s, ", {x:.1}x floor");
                }
                if let Some(m) = self.mem_bytes_per_body {
                    let _ = write!(s, ", {m:.0} B/body");
                }
                if !self.note.is_empty() {
                    let _ = write!(s, " [{}]", self.note);
                }
                s
            }
        }
    }

    fn csv_fields(&self) -> Vec<String> {
        vec![
            self.scene.clone(),
            self.bodies.to_string(),
            self.engine.clone(),
            self.steps.to_string(),
            opt(self.median_ms),
            opt(self.p90_ms),
            opt(self.drift_m),
            opt(self.lowest_m),
            opt(self.gpu_ms),
            self.bytes_per_step.map_or(String::new(), |b| b.to_string()),
            opt(self.floor_ms),
            opt(self.x_floor),
            opt(self.mem_bytes_per_body),
            self.manifolds.map_or(String::new(), |m| m.to_string()),
            self.note.clone(),
        ]
    }

    fn from_fields(header: &[String], fields: &[String]) -> Result<Self, String> {
        let get = |name: &str| {
            header
                .iter()
                .position(|h| h == name)
                .and_then(|i| fields.get(i))
                .map(|s| s.trim())
                .unwrap_or("")
        };
        let num = |name: &str| -> Result<Option<f64>, String> {
            let v = get(name);
            if v.is_empty() || v.eq_ignore_ascii_case("nan") {
                Ok(None)
            } else {
                v.parse()
                    .map(Some)
                    .map_err(|_| format!("column {name}: {v:?} is not a number"))
            }
        };
        let int = |name: &str| -> Result<Option<u64>, String> {
            Ok(num(name)?.map(|v| v.round() as u64))
        };
        if get("scene").is_empty() || get("engine").is_empty() {
            return Err("a row without scene or engine".into());
        }
        Ok(Self {
            scene: get("scene").to_owned(),
            bodies: int("bodies")?.unwrap_or(0) as usize,
            engine: get("engine").to_owned(),
            steps: int("steps")?.unwrap_or(0) as usize,
            median_ms: num("median_ms")?,
            p90_ms: num("p90_ms")?,
            drift_m: num("drift_m")?,
            lowest_m: num("lowest_m")?,
            gpu_ms: num("gpu_ms")?,
            bytes_per_step: int("bytes_per_step")?,
            floor_ms: num("floor_ms")?,
            x_floor: num("x_floor")?,
            mem_bytes_per_body: num("mem_bytes_per_body")?,
            manifolds: int("manifolds")?,
            note: get("note").to_owned(),
        })
    }
}

fn percentile(sorted: &[f64], q: f64) -> Option<f64> {
    if sorted.is_empty() {
        return None;
    }
    let i = ((sorted.len() - 1) as f64 * q).round() as usize;
    Some(sorted[i])
}

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |v| format!("{v:.6}"))
}

fn fmt(v: Option<f64>, digits: usize) -> String {
    v.map_or("-".to_owned(), |v| format!("{v:.digits$}"))
}

/// Writes results.csv (unless `passes` is empty and the rows came from it), passes.csv,
/// table.md and ms_per_step.png into `dir`, and prints the table.
pub fn write_outputs(
    dir: &Path,
    rows: &[Row],
    passes: &[(String, String, f64, usize)],
    nexus: &[Row],
    bandwidth_gbs: f64,
    header: &str,
) -> Result<(), String> {
    let write = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| format!("writing {}: {e}", path.display()))
    };
    if !header.is_empty() {
        write("results.csv", &csv_text(rows))?;
        let mut pass_csv = String::from("scene,pass,ms_per_step,passes_per_step\n");
        for (scene, pass, ms, count) in passes {
            let _ = writeln!(pass_csv, "{scene},{},{ms:.6},{count}", csv_escape(pass));
        }
        write("passes.csv", &pass_csv)?;
    }
    let mut md = String::new();
    if !header.is_empty() {
        let _ = writeln!(md, "```text\n{header}\n```\n");
    }
    md.push_str(&markdown_table(rows, nexus));
    let _ = writeln!(
        md,
        "\nMB/step: the traffic model of `xtask/src/bench_gpu_report/traffic.rs`; floor ms = bytes / \
         {bandwidth_gbs} GB/s; x floor = GPU ms (wall ms without timestamps) / floor ms. \
         Drift: largest horizontal displacement of a dynamic body at the end of the run; \
         lowest: lowest dynamic body's centre along the up axis."
    );
    md.push_str(&pass_tables(passes));
    write("table.md", &md)?;
    println!("\n{md}");
    let png = dir.join("ms_per_step.png");
    plot(&png, rows, nexus)?;
    println!(
        "wrote {} (results.csv, passes.csv, table.md, ms_per_step.png)",
        dir.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_survive_the_csv_round_trip() {
        let mut row = Row::new("pyramid_8", 205, "tumble-gpu");
        row.set_times(&[3.0, 1.0, 2.0]);
        row.drift_m = Some(0.001);
        row.note = "a, \"quoted\" note".into();
        let text = csv_text(std::slice::from_ref(&row));
        let records = parse_csv(&text);
        let header = records[0].clone();
        let back = Row::from_fields(&header, &records[1]).unwrap();
        assert_eq!(back.note, row.note);
        assert_eq!(back.median_ms, Some(2.0));
        assert_eq!(back.p90_ms, Some(3.0));
        assert_eq!(back.steps, 3);
    }

    #[test]
    fn the_table_gives_ratios_against_the_peers() {
        let mut gpu = Row::new("s", 10, "tumble-gpu");
        gpu.median_ms = Some(2.0);
        let mut rapier = Row::new("s", 10, "rapier3d");
        rapier.median_ms = Some(8.0);
        let mut nexus = Row::new("s", 10, "nexus");
        nexus.median_ms = Some(1.0);
        let table = markdown_table(&[gpu, rapier], &[nexus]);
        let gpu_line = table.lines().find(|l| l.contains("tumble-gpu")).unwrap();
        assert!(gpu_line.contains("| 4.00 | 2.00 |"), "{gpu_line}");
    }

    #[test]
    fn traffic_grows_with_substeps() {
        let counts = TrafficCounts {
            bodies: 100,
            manifolds: 300,
            points: 1200,
            substeps: 4,
        };
        let more = TrafficCounts {
            substeps: 8,
            ..counts
        };
        assert!(more.bytes_per_step() > counts.bytes_per_step());
        assert_eq!(group_thousands(338_351), "338,351");
    }
}
