//! `cargo xtask bench-gpu`: milliseconds per step of Tumble's GPU step beside rapier3d (on all
//! cores) and, from a CSV the peer script `benches/peers/nexus_scenes.py` writes, nexus, on
//! the same scene files. See docs/benchmarks.md, "Running the GPU benchmark".
//!
//! Per scene and engine: wall time per step (median, p90) with one pose read per step (a GPU
//! step is finished and its results on the host before the clock stops), the largest
//! horizontal drift of any dynamic body and the lowest body's height along the scene's up
//! axis at the end of the run. For `Backend::Gpu`, a second, timestamped run of the same
//! scene gives the per-pass GPU times, the GPU memory per body (the world's pooled buffers)
//! and the bytes moved per step by the traffic model of [`crate::bench_gpu_report`].
//!
//! The binary needs no cargo at run time: `xtask bench-gpu ...` from the repository root
//! writes under `target/bench-gpu` (relative to the current folder) unless `--out` says
//! otherwise.

mod profile;
mod runs;
mod scenes;

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use clap::Args;
use tumble::prelude::*;
use tumble_gpu::GpuContext;
use tumble_gpu::step::{GpuWorld, GpuWorldConfig, ReadRequest};
use tumble_scenes::{BodySpec, RapierOptions, Scene, build_rapier_with, builders};

use crate::bench_gpu_report::{self as report, Row, TrafficCounts};

use profile::*;
use runs::*;
use scenes::*;

/// Options of `cargo xtask bench-gpu`.
#[derive(Args, Debug)]
pub struct BenchGpuArgs {
    /// Scenes, comma-separated: stackN, pyramidH (packed, tumble-scenes' builder), poolN (N
    /// unit cubes in columns of 16 on a floor), droppoolN (N boxes of mixed sizes dropped into
    /// a walled pool), nexus_pyramidH; N may end in k or m (pool1m, droppool10k) [default:
    /// stack20, pyramid24, pyramid50, pyramid100, nexus_pyramid50, pool1000000, droppool1m;
    /// with --quick: stack20, pyramid8, pool10000, droppool10k].
    #[arg(long, value_delimiter = ',', value_name = "LIST")]
    pub scenes: Option<Vec<String>>,
    /// Engines, comma-separated: gpu, rapier, cpu, hybrid.
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "LIST",
        default_value = "gpu,rapier"
    )]
    pub backends: Vec<String>,
    /// Timed steps per run (after the warm-up); a run whose budget is spent stops earlier.
    #[arg(long, default_value_t = 60)]
    pub steps: usize,
    /// Substeps (Tumble's soft step) and solver iterations (rapier3d's substeps).
    #[arg(long, default_value_t = 4)]
    pub substeps: u32,
    /// Small scenes (pyramid of 8, 10,000-box pool) and 20 steps: minutes on lavapipe.
    #[arg(long)]
    pub quick: bool,
    /// Seconds one engine may spend on one scene's warm-up and timed steps: slow rows (rapier3d
    /// on the largest scenes) time fewer steps, at least 5, and say so in their notes.
    #[arg(long, default_value_t = 35.0, value_name = "SECONDS")]
    pub budget_s: f64,
    /// Memory bandwidth of the device in GB/s, for the floor time bytes / bandwidth (default:
    /// an H200's HBM3e).
    #[arg(long, default_value_t = 4800.0, value_name = "GB/S")]
    pub bandwidth_gbs: f64,
    /// Output folder: results.csv, passes.csv, ms_per_step.png, table.md.
    #[arg(long, value_name = "DIR", default_value = "target/bench-gpu")]
    pub out: PathBuf,
    /// Only write the selected scenes as JSON files into DIR (for benches/peers/nexus_scenes.py)
    /// and exit.
    #[arg(long, value_name = "DIR")]
    pub write_scenes: Option<PathBuf>,
    /// A CSV from benches/peers/nexus_scenes.py: its rows join the table, with Tumble/nexus
    /// ratios per scene.
    #[arg(long, value_name = "FILE")]
    pub nexus_csv: Option<PathBuf>,
    /// Make no new runs: rebuild the table and plot from DIR/results.csv (with --nexus-csv).
    #[arg(long)]
    pub report_only: bool,
    /// Internal: run only the timestamped GPU profile of this scene and print it as JSON. The
    /// profile runs in a process of its own because wgpu device handles from different
    /// instances are not told apart by the engine's pipeline cache.
    #[arg(long, hide = true, value_name = "SCENE")]
    pub profile_scene: Option<String>,
}

/// Runs the task; `Ok(false)` when a requested row could not run.
pub fn bench_gpu(args: &BenchGpuArgs) -> Result<bool, String> {
    let names: Vec<String> = match &args.scenes {
        Some(list) => list.iter().map(|s| s.trim().to_owned()).collect(),
        None if args.quick => QUICK_SCENES.iter().map(|s| (*s).to_owned()).collect(),
        None => DEFAULT_SCENES.iter().map(|s| (*s).to_owned()).collect(),
    };
    if let Some(name) = &args.profile_scene {
        return print_profile(name, args.substeps, Duration::from_secs_f64(args.budget_s));
    }
    if let Some(dir) = &args.write_scenes {
        write_scenes(dir, &names)?;
        return Ok(true);
    }
    let engines = args
        .backends
        .iter()
        .map(|b| Engine::parse(b))
        .collect::<Result<Vec<_>, _>>()?;
    if args.steps == 0 || args.substeps == 0 {
        return Err("--steps and --substeps must be at least 1".into());
    }
    if args.bandwidth_gbs.is_nan() || args.bandwidth_gbs <= 0.0 {
        return Err("--bandwidth-gbs must be positive".into());
    }
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("creating {}: {e}", args.out.display()))?;
    let nexus = match &args.nexus_csv {
        Some(path) => report::read_csv(path)?,
        None => Vec::new(),
    };
    if args.report_only {
        let rows = report::read_csv(&args.out.join("results.csv"))?;
        report::write_outputs(&args.out, &rows, &[], &nexus, args.bandwidth_gbs, "")?;
        return Ok(true);
    }
    let steps = if args.quick {
        args.steps.min(20)
    } else {
        args.steps
    };
    let wants_gpu = engines
        .iter()
        .any(|e| matches!(e, Engine::Tumble(Backend::Gpu | Backend::Hybrid)));
    let ctx = if wants_gpu {
        Some(GpuContext::new().map_err(|e| format!("no GPU adapter: {e}"))?)
    } else {
        None
    };
    let mut header = format!(
        "steps {steps} (+ up to {WARMUP_STEPS} warm-up), substeps {}, budget {} s per run, \
         bandwidth floor {} GB/s; rapier3d: {}",
        args.substeps,
        args.budget_s,
        args.bandwidth_gbs,
        rapier_threads()
    );
    if let Some(ctx) = &ctx {
        let limits = ctx.limits();
        header.push_str(&format!(
            "\nadapter: {} ({:?}, {:?}), timestamps {}, max storage binding {} MiB",
            ctx.info.name,
            ctx.info.backend,
            ctx.info.device_type,
            if ctx.has_timestamps { "yes" } else { "no" },
            limits.max_storage_buffer_binding_size >> 20
        ));
    }
    // Only for the adapter's description: the runs open their own devices.
    drop(ctx);
    println!("{header}");
    let mut rows = Vec::new();
    let mut passes = Vec::new();
    let mut all_ran = true;
    for name in &names {
        let scene = match scene_named(name) {
            Ok(scene) => scene,
            Err(e) => {
                println!("\n{name}: {e}");
                continue;
            }
        };
        println!("\n{name}: {} bodies", scene.bodies.len());
        for &engine in &engines {
            let clock = Instant::now();
            let mut row = run_engine(&scene, engine, args, steps);
            if let (Engine::Tumble(Backend::Gpu), Some(_)) = (engine, row.median_ms) {
                match profile_in_child(name, args.substeps, args.budget_s) {
                    Ok(profile) => {
                        row.gpu_ms = (!profile.passes.is_empty())
                            .then(|| profile.passes.iter().map(|p| p.1).sum());
                        row.bytes_per_step = Some(profile.traffic.bytes_per_step());
                        row.mem_bytes_per_body =
                            Some(profile.buffer_bytes as f64 / scene.bodies.len() as f64);
                        row.manifolds = Some(profile.traffic.manifolds);
                        for (pass, ms, count) in profile.passes {
                            passes.push((scene.name.clone(), pass, ms, count));
                        }
                    }
                    Err(e) => row.note = format!("{}; profile failed: {e}", row.note),
                }
            }
            row.fill_floor(args.bandwidth_gbs);
            all_ran &= row.median_ms.is_some();
            println!(
                "  {:<14} {}  ({:.1} s)",
                engine.name(),
                row.summary(),
                clock.elapsed().as_secs_f64()
            );
            rows.push(row);
        }
    }
    report::write_outputs(
        &args.out,
        &rows,
        &passes,
        &nexus,
        args.bandwidth_gbs,
        &header,
    )?;
    Ok(all_ran)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pool_holds_n_cubes_resting_in_columns() {
        let scene = box_pool(1000);
        assert_eq!(scene.bodies.len(), 1001);
        assert!(scene.validate().is_ok());
        let lowest = scene.bodies[1..]
            .iter()
            .map(|b| b.position[1])
            .fold(f32::INFINITY, f32::min);
        assert_eq!(lowest, 0.5);
        let (drift, low) = drift_and_lowest(
            &scene,
            &scene.bodies.iter().map(|b| b.position).collect::<Vec<_>>(),
        );
        assert_eq!((drift, low), (0.0, 0.5));
    }

    #[test]
    fn the_dropped_pool_holds_n_boxes_of_mixed_sizes_apart_inside_its_walls() {
        let scene = drop_pool(2000);
        // Floor, four walls, then the boxes.
        assert_eq!(scene.bodies.len(), 2005);
        assert!(scene.validate().is_ok());
        let boxes = &scene.bodies[5..];
        let aabb = |b: &BodySpec| {
            let (p, h) = (b.position, b.half_extents);
            (
                [p[0] - h[0], p[1] - h[1], p[2] - h[2]],
                [p[0] + h[0], p[1] + h[1], p[2] + h[2]],
            )
        };
        let tumble_scenes::SceneCheck::Contained { min, max } = scene.check else {
            panic!("the pool is checked for containment");
        };
        for b in boxes {
            let (lo, hi) = aabb(b);
            // Inside the walls and above the floor from the start.
            assert!((0..3).all(|k| lo[k] > min[k] && hi[k] < max[k]), "{b:?}");
        }
        // Boxes start apart: no two axis-aligned boxes overlap (each is inside its own cell,
        // DROP_SIDE_GAP from its sides; a brute-force check of all pairs of the first layer
        // and the next one).
        let check = &boxes[..boxes.len().min(300)];
        for (i, a) in check.iter().enumerate() {
            let (alo, ahi) = aabb(a);
            for b in &check[i + 1..] {
                let (blo, bhi) = aabb(b);
                assert!(
                    (0..3).any(|k| ahi[k] <= blo[k] || bhi[k] <= alo[k]),
                    "{a:?} {b:?}"
                );
            }
        }
        // Mixed sizes: the extents spread over most of DROP_HALF's range.
        let halves: Vec<f32> = boxes.iter().map(|b| b.half_extents[1]).collect();
        let (small, large) = halves
            .iter()
            .fold((f32::INFINITY, 0.0f32), |(s, l), &h| (s.min(h), l.max(h)));
        assert!(small < 0.27 && large > 0.58, "{small} {large}");
    }

    #[test]
    fn scene_names_give_the_benchmark_sizes() {
        assert_eq!(scene_named("pool10k").unwrap().bodies.len(), 10_001);
        assert_eq!(scene_named("droppool1k").unwrap().bodies.len(), 1_005);
        assert!(scene_named("pool1x").is_err());
        assert_eq!(scene_named("pyramid24").unwrap().bodies.len(), 4_901);
        assert_eq!(scene_named("stack20").unwrap().bodies.len(), 21);
        assert!(scene_named("nexus_pyramid50").is_err());
        assert!(scene_named("cube").is_err());
    }

    #[test]
    fn a_slow_run_is_cut_to_its_budget() {
        let (ms, note) = timed_steps(100, Duration::from_millis(30), || {
            std::thread::sleep(Duration::from_millis(2));
            Ok(())
        })
        .unwrap();
        assert!(
            ms.len() >= MIN_TIMED_STEPS && ms.len() < 100,
            "{}",
            ms.len()
        );
        assert!(note.starts_with("budget"));
    }
}
