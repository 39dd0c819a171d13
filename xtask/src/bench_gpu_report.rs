//! `bench-gpu`'s rows and outputs: the CSV (shared with `benches/peers/nexus_scenes.py`), the
//! markdown table, the per-pass table and the log-log plot; and the traffic model behind the
//! "bytes per step" column.
//!
//! # The traffic model
//!
//! Bytes a GPU step must move at least, counted from the record sizes of the buffers each pass
//! reads and writes (`tumble_gpu::layout` and `tumble_gpu::solver::layout`, so the count
//! follows the engine's own structs) times the passes per step; every record is taken to
//! cross the memory bus once per pass that touches it (no cache reuse, no bank conflicts).
//! With `N` bodies, `M` manifolds with contact points, `P` contact points and `S` substeps:
//!
//! | pass | bytes |
//! |---|---|
//! | update_aabbs | `N * (pose + velocity + shape + aabb)` |
//! | broad phase | `N * (4 radix passes * 2 * 8 + aabb) + M * 8` (sorted keys, the sweep, the pair list) |
//! | narrow phase | `M * 2 * (pose + shape + manifold) + P * 2 * contact` (inputs, the previous manifold matched, the new one written) |
//! | prepare | `M * (manifold + constraint) + P * contact` |
//! | each substep | `N * 4 * (velocity + solver body)` (integrate velocities, positions) `+ 3 * M * (constraint + 2 * (2 * velocity + solver body))` (warm start, solve, relax: each reads its constraint, whose impulse writes are counted nowhere, and reads and writes both bodies' velocities) |
//! | restitution, finish | `M * (3 * constraint + 2 * (2 * velocity + solver body)) + N * (solver body + pose + velocity)` |
//!
//! The pair sort, the coloring rounds and the sleep stage are left out: the model is a floor,
//! and `x floor` (the measured time over bytes / bandwidth) says how far a step is from
//! streaming its data once at the device's bandwidth.

use std::fmt::Write as _;
use std::path::Path;

use plotters::prelude::*;
use tumble_gpu::layout::{GpuAabb, GpuContact, GpuManifold, GpuPose, GpuShape, GpuVelocity};
use tumble_gpu::solver::layout::{GpuConstraint, GpuSolverBody};

use crate::fonts::{PLOT_FONT, register_plot_font};

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

/// The counts the traffic model needs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TrafficCounts {
    /// Bodies, fixed ones included.
    pub bodies: u64,
    /// Manifolds with contact points.
    pub manifolds: u64,
    /// Contact points.
    pub points: u64,
    /// Substeps per step.
    pub substeps: u64,
}

impl TrafficCounts {
    /// Bytes per step by the model of this module's documentation.
    pub fn bytes_per_step(&self) -> u64 {
        let size = |s: usize| s as u64;
        let pose = size(size_of::<GpuPose>());
        let velocity = size(size_of::<GpuVelocity>());
        let shape = size(size_of::<GpuShape>());
        let aabb = size(size_of::<GpuAabb>());
        let manifold = size(size_of::<GpuManifold>());
        let contact = size(size_of::<GpuContact>());
        let constraint = size(size_of::<GpuConstraint>());
        let solver_body = size(size_of::<GpuSolverBody>());
        let Self {
            bodies: n,
            manifolds: m,
            points: p,
            substeps: s,
        } = *self;
        let body_pair = 2 * (2 * velocity + solver_body);
        let update_aabbs = n * (pose + velocity + shape + aabb);
        let broad = n * (4 * 2 * 8 + aabb) + m * 8;
        let narrow = m * 2 * (pose + shape + manifold) + p * 2 * contact;
        let prepare = m * (manifold + constraint) + p * contact;
        let substep = n * 4 * (velocity + solver_body) + 3 * m * (constraint + body_pair);
        let finish = m * (3 * constraint + body_pair) + n * (solver_body + pose + velocity);
        update_aabbs + broad + narrow + prepare + s * substep + finish
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

fn csv_escape(field: &str) -> String {
    if field.contains([',', '"', '\n']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_owned()
    }
}

/// Splits CSV text into records of fields (quoted fields, doubled quotes and CRLF as Python's
/// `csv` module writes them).
fn parse_csv(text: &str) -> Vec<Vec<String>> {
    let mut records = Vec::new();
    let mut record = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') => quoted = true,
            (false, ',') => record.push(std::mem::take(&mut field)),
            (false, '\r') => {}
            (false, '\n') => {
                record.push(std::mem::take(&mut field));
                records.push(std::mem::take(&mut record));
            }
            (false, c) => field.push(c),
        }
    }
    if !field.is_empty() || !record.is_empty() {
        record.push(field);
        records.push(record);
    }
    records
        .into_iter()
        .filter(|r| !(r.len() == 1 && r[0].trim().is_empty()))
        .collect()
}

/// Rows of a CSV with [`CSV_COLUMNS`] (by name, in any order; missing columns are empty).
pub fn read_csv(path: &Path) -> Result<Vec<Row>, String> {
    let text =
        std::fs::read_to_string(path).map_err(|e| format!("reading {}: {e}", path.display()))?;
    let mut records = parse_csv(&text).into_iter();
    let header: Vec<String> = records
        .next()
        .ok_or_else(|| format!("{} is empty", path.display()))?
        .into_iter()
        .map(|h| h.trim().to_owned())
        .collect();
    for needed in ["scene", "engine", "median_ms"] {
        if !header.iter().any(|h| h == needed) {
            return Err(format!("{}: no column {needed}", path.display()));
        }
    }
    records
        .enumerate()
        .map(|(i, r)| {
            Row::from_fields(&header, &r)
                .map_err(|e| format!("{} line {}: {e}", path.display(), i + 2))
        })
        .collect()
}

fn csv_text(rows: &[Row]) -> String {
    let mut text = CSV_COLUMNS.join(",");
    text.push('\n');
    for row in rows {
        let fields: Vec<String> = row.csv_fields().iter().map(|f| csv_escape(f)).collect();
        text.push_str(&fields.join(","));
        text.push('\n');
    }
    text
}

/// The markdown table of `rows` (Tumble's and rapier3d's) and `nexus`'s, grouped by scene in
/// the order of `rows`, with ratios against rapier3d and nexus on the same scene.
pub fn markdown_table(rows: &[Row], nexus: &[Row]) -> String {
    let mut scenes: Vec<&str> = Vec::new();
    for r in rows.iter().chain(nexus) {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    let mut s = String::from(
        "| scene | bodies | engine | steps | median ms/step | p90 ms/step | rapier3d / this | \
         this / nexus | drift (mm) | lowest (m) | GPU ms (timestamps) | MB/step (model) | \
         floor ms | x floor | GPU bytes/body | notes |\n\
         |---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n",
    );
    for scene in scenes {
        let of_scene: Vec<&Row> = rows
            .iter()
            .chain(nexus)
            .filter(|r| r.scene == scene)
            .collect();
        let median_of = |engine: &str| {
            of_scene
                .iter()
                .find(|r| r.engine == engine)
                .and_then(|r| r.median_ms)
        };
        let rapier = median_of("rapier3d");
        let nexus_ms = median_of("nexus");
        for r in &of_scene {
            let ratio = |peer: Option<f64>, over: bool| match (peer, r.median_ms) {
                (Some(p), Some(m)) if m > 0.0 && p > 0.0 => {
                    let x = if over { p / m } else { m / p };
                    if x < 0.1 {
                        format!("{x:.4}")
                    } else {
                        format!("{x:.2}")
                    }
                }
                _ => String::new(),
            };
            let vs_rapier = if r.engine == "rapier3d" {
                String::new()
            } else {
                ratio(rapier, true)
            };
            let vs_nexus = if r.engine.starts_with("tumble") {
                ratio(nexus_ms, false)
            } else {
                String::new()
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                r.scene,
                group_thousands(r.bodies as u64),
                r.engine,
                r.steps,
                fmt(r.median_ms, 3),
                fmt(r.p90_ms, 3),
                vs_rapier,
                vs_nexus,
                fmt(r.drift_m.map(|d| d * 1e3), 2),
                fmt(r.lowest_m, 3),
                fmt(r.gpu_ms, 3),
                fmt(r.bytes_per_step.map(|b| b as f64 / 1e6), 1),
                fmt(r.floor_ms, 3),
                fmt(r.x_floor, 1),
                fmt(r.mem_bytes_per_body, 0),
                r.note.replace('|', "/"),
            );
        }
    }
    s
}

fn group_thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// The per-pass tables: one per scene, passes by GPU time.
fn pass_tables(passes: &[(String, String, f64, usize)]) -> String {
    let mut s = String::new();
    let mut scenes: Vec<&str> = Vec::new();
    for (scene, ..) in passes {
        if !scenes.contains(&scene.as_str()) {
            scenes.push(scene);
        }
    }
    for scene in scenes {
        let of_scene: Vec<_> = passes.iter().filter(|p| p.0 == scene).collect();
        let total: f64 = of_scene.iter().map(|p| p.2).sum();
        let _ = write!(
            s,
            "\n### {scene}: GPU time per pass (timestamps, tumble-gpu)\n\n\
             | pass | ms/step | passes/step | share |\n|---|---:|---:|---:|\n"
        );
        for (_, pass, ms, count) in of_scene {
            let share = if total > 0.0 { 100.0 * ms / total } else { 0.0 };
            let _ = writeln!(s, "| {pass} | {ms:.3} | {count} | {share:.1}% |");
        }
        let _ = writeln!(s, "| GPU total | {total:.3} | | |");
    }
    s
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
        "\nMB/step: the traffic model of `xtask/src/bench_gpu_report.rs`; floor ms = bytes / \
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

/// Colour per engine (Tableau colours).
fn engine_color(engine: &str) -> RGBColor {
    match engine {
        "tumble-gpu" => RGBColor(214, 39, 40),
        "tumble-hybrid" => RGBColor(255, 127, 14),
        "tumble-cpu" => RGBColor(148, 103, 189),
        "rapier3d" => RGBColor(31, 119, 180),
        "nexus" => RGBColor(44, 160, 44),
        _ => RGBColor(127, 127, 127),
    }
}

/// Milliseconds per step against bodies, log-log, one line per engine.
fn plot(path: &Path, rows: &[Row], nexus: &[Row]) -> Result<(), String> {
    register_plot_font();
    let mut engines: Vec<&str> = Vec::new();
    let points: Vec<(&str, f64, f64)> = rows
        .iter()
        .chain(nexus)
        .filter_map(|r| {
            let ms = r.median_ms.filter(|&m| m > 0.0)?;
            (r.bodies > 0).then_some((r.engine.as_str(), r.bodies as f64, ms))
        })
        .collect();
    for (e, ..) in &points {
        if !engines.contains(e) {
            engines.push(e);
        }
    }
    if points.is_empty() {
        println!("no timed rows: no plot");
        return Ok(());
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(_, x, y) in &points {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let (x0, x1) = (x0 / 2.0, x1 * 2.0);
    let (y0, y1) = (y0 / 2.0, y1 * 2.0);
    let root = BitMapBackend::new(path, (1000, 700)).into_drawing_area();
    let err = |e: DrawingAreaErrorKind<_>| format!("plotting {}: {e}", path.display());
    root.fill(&WHITE).map_err(err)?;
    let mut chart = ChartBuilder::on(&root)
        .caption("wall time per step against bodies", (PLOT_FONT, 24))
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("bodies")
        .y_desc("ms per step (median)")
        .label_style((PLOT_FONT, 16))
        .draw()
        .map_err(err)?;
    for engine in engines {
        let color = engine_color(engine);
        let mut line: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.0 == engine)
            .map(|p| (p.1, p.2))
            .collect();
        line.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart
            .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
            .map_err(err)?
            .label(engine)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        chart
            .draw_series(line.into_iter().map(|p| Circle::new(p, 4, color.filled())))
            .map_err(err)?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font((PLOT_FONT, 16))
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
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
