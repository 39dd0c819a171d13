//! The markdown tables: one row per scene and engine, and the per-pass GPU times.

use super::*;

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

pub(super) fn group_thousands(n: u64) -> String {
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
pub(super) fn pass_tables(passes: &[(String, String, f64, usize)]) -> String {
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
