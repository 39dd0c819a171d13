//! World-steps per second for batches of small worlds: Tumble's `WorldBatch` on the GPU (one
//! device world for all worlds of one config) and on the CPU (one rayon task per world), and
//! rapier3d stepping the same worlds on all cores (one share of the worlds per thread), measured
//! side by side in one run.
//!
//! ```sh
//! cargo run --release -p tumble-benches --bin batch_table -- \
//!     --columns 1,64,1024,4096,16384 --pyramids 1024 --csv target/batch/batch.csv
//! ```
//!
//! Each row steps N copies of one scene (a column of 20 unit cubes on its own floor, or a
//! pyramid of `--pyramid-height` layers) at 60 Hz with `--substeps` substeps (rapier3d with as
//! many solver iterations, each of which is a substep in its soft-step solver), and reports
//! the median and 90th percentile over `--repeats` timed runs of `--steps` steps, each run
//! ending in a read of every pose (on the GPU the run's wall time therefore includes all of
//! its GPU work), the microseconds per world-step, and the largest horizontal drift of any
//! dynamic body of any world at the end: a faster row counts only if its worlds stand as well.
//! `--read-every-step` adds GPU rows that read every pose after every step (as a training
//! loop that looks at every step would). `--write-scene FILE` writes the column's JSON (for
//! `benches/peers/nexus_batch.py`) and exits.

use std::time::Instant;

use clap::Parser;
use rayon::prelude::*;
use tumble::EffectOverrides;
use tumble::prelude::*;
use tumble::{FrictionPasses, POSE_FLOATS, WorldBatch};
use tumble_scenes::{RapierOptions, RapierWorld, Scene, build_rapier_with, builders};

/// World-steps per second for batches of small worlds.
#[derive(Parser, Debug)]
struct Args {
    /// Batch sizes of columns of 20, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "1,64,1024,4096")]
    columns: Vec<usize>,
    /// Batch sizes of small pyramids, comma-separated (none by default).
    #[arg(long, value_delimiter = ',')]
    pyramids: Vec<usize>,
    /// Layers of the small pyramids.
    #[arg(long, default_value_t = 4)]
    pyramid_height: usize,
    /// Engines, comma-separated: gpu, cpu, rapier.
    #[arg(long, value_delimiter = ',', default_value = "gpu,cpu,rapier")]
    engines: Vec<String>,
    /// Largest batch the CPU engines (Tumble's CPU backend, rapier3d) run.
    #[arg(long, default_value_t = 16384)]
    cpu_max_worlds: usize,
    /// Steps per timed run.
    #[arg(long, default_value_t = 60)]
    steps: usize,
    /// Timed runs per row.
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Steps before timing starts.
    #[arg(long, default_value_t = 10)]
    warmup: usize,
    /// GPU rows keep stepping after the warm-up steps until this many milliseconds have
    /// passed since the batch was built (0: the warm-up steps only), so that the GPU has left
    /// its idle clocks when timing starts: an H100 idles at 345 of its 1,980 MHz, and a first
    /// row timed from there measured 1.28 against 0.53 ms at 1,024 columns.
    #[arg(long, default_value_t = 500)]
    gpu_warmup_ms: u64,
    /// Substeps per step (rapier3d: solver iterations).
    #[arg(long, default_value_t = 4)]
    substeps: u32,
    /// Also time GPU runs that read every pose after every step.
    #[arg(long)]
    read_every_step: bool,
    /// Tumble's rows with friction in the relax passes only
    /// (`SolverConfig::friction_passes = FrictionPasses::RelaxOnly`) instead of every pass.
    #[arg(long)]
    relax_only_friction: bool,
    /// Writes the rows here as CSV too.
    #[arg(long)]
    csv: Option<String>,
    /// Writes the column scene's JSON here and exits.
    #[arg(long)]
    write_scene: Option<String>,
}

/// One measured row.
struct Row {
    case: String,
    worlds: usize,
    bodies: usize,
    engine: String,
    median_ms: f64,
    p90_ms: f64,
    drift_m: f64,
    note: String,
}

/// The scene of a case: the column of 20, or the small pyramid.
fn scene_of(case: &str, height: usize) -> Scene {
    match case {
        "column20" => builders::stack(20),
        _ => builders::pyramid(height),
    }
}

/// Largest horizontal (x, z) displacement of a dynamic body from its start, over all worlds.
fn drift(starts: &[Vec<(Vec3, bool)>], poses: &[f32]) -> f64 {
    let mut worst = 0.0f64;
    let mut i = 0;
    for world in starts {
        for (start, dynamic) in world {
            let p = &poses[i * POSE_FLOATS..];
            if *dynamic {
                let dx = f64::from(p[0] - start.x);
                let dz = f64::from(p[2] - start.z);
                worst = worst.max((dx * dx + dz * dz).sqrt());
            }
            i += 1;
        }
    }
    worst
}

fn median_p90(mut v: Vec<f64>) -> (f64, f64) {
    v.sort_by(f64::total_cmp);
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    (at(0.5), at(0.9))
}

fn run_tumble(
    args: &Args,
    scene: &Scene,
    worlds: usize,
    backend: Backend,
    read_every_step: bool,
) -> Result<(Vec<f64>, f64, String), Error> {
    let config = WorldConfig {
        backend,
        solver: SolverConfig {
            substeps: args.substeps,
            friction_passes: if args.relax_only_friction {
                FrictionPasses::RelaxOnly
            } else {
                FrictionPasses::Every
            },
            ..SolverConfig::default()
        },
        effects: EffectOverrides::NO_SLEEP,
        ..WorldConfig::default()
    };
    let built = Instant::now();
    let scenes = vec![scene.clone(); worlds];
    let mut batch = WorldBatch::from_scenes(&scenes, config)?;
    let build_s = built.elapsed().as_secs_f64();
    let ids = batch.ids();
    let mut starts = Vec::with_capacity(worlds);
    for &id in &ids {
        let world = batch.world(id)?;
        starts.push(
            world
                .handles()
                .iter()
                .map(|&h| {
                    let p = world.pose(h).unwrap().translation.vector;
                    (p, world.kind(h).unwrap() == BodyKind::Dynamic)
                })
                .collect::<Vec<_>>(),
        );
    }
    let mut poses = vec![0.0f32; batch.all_poses_len()];
    let warming = Instant::now();
    for _ in 0..args.warmup {
        batch.step()?;
    }
    if backend == Backend::Gpu {
        while warming.elapsed().as_millis() < u128::from(args.gpu_warmup_ms) {
            batch.step()?;
        }
    }
    batch.read_all_poses(&mut poses)?;
    let mut samples = Vec::new();
    let mut host = 0.0;
    for _ in 0..args.repeats {
        let t0 = Instant::now();
        for _ in 0..args.steps {
            let h = Instant::now();
            batch.step()?;
            host += h.elapsed().as_secs_f64();
            if read_every_step {
                batch.read_all_poses(&mut poses)?;
            }
        }
        batch.read_all_poses(&mut poses)?;
        samples.push(t0.elapsed().as_secs_f64() * 1e3 / args.steps as f64);
    }
    let host_ms = host * 1e3 / (args.repeats * args.steps) as f64;
    // The last step's GPU time per stage (timestamps), summed.
    let stages = batch.device_timings()?;
    let gpu_ms: f64 = stages.iter().map(|(_, s)| s).sum::<f64>() * 1e3;
    let mut top: Vec<_> = stages.clone();
    top.sort_by(|a, b| b.1.total_cmp(&a.1));
    let top: Vec<String> = top
        .iter()
        .take(4)
        .map(|(n, s)| format!("{n} {:.3}", s * 1e3))
        .collect();
    let note = format!(
        "host {host_ms:.3} ms in step(); GPU {gpu_ms:.3} ms by timestamps ({}); {} device \
         world(s), {:.1} MiB of GPU buffers; built in {build_s:.2} s",
        top.join(", "),
        batch.device_worlds(),
        batch.device_buffer_bytes() as f64 / (1 << 20) as f64
    );
    Ok((samples, drift(&starts, &poses), note))
}

fn run_rapier(args: &Args, scene: &Scene, worlds: usize) -> (Vec<f64>, f64, String) {
    let options = RapierOptions {
        solver_iterations: args.substeps as usize,
        ..RapierOptions::default()
    };
    let mut all: Vec<RapierWorld> = (0..worlds)
        .into_par_iter()
        .map(|_| build_rapier_with(scene, &options))
        .collect();
    let starts: Vec<Vec<(Vec3, bool)>> = vec![
        scene
            .bodies
            .iter()
            .map(|b| (
                Vec3::from(b.position),
                b.kind == tumble_scenes::BodyKind::Dynamic
            ))
            .collect();
        worlds
    ];
    let threads = rayon::current_num_threads();
    step_rapier_worlds(&mut all, args.warmup, threads);
    let mut samples = Vec::new();
    for _ in 0..args.repeats {
        let t0 = Instant::now();
        step_rapier_worlds(&mut all, args.steps, threads);
        samples.push(t0.elapsed().as_secs_f64() * 1e3 / args.steps as f64);
    }
    let mut poses = Vec::with_capacity(worlds * scene.bodies.len() * POSE_FLOATS);
    for w in &all {
        for (t, q) in w.body_poses() {
            poses.extend_from_slice(&t);
            poses.extend_from_slice(&q);
        }
    }
    let note = format!("the worlds in {threads} shares, a thread each");
    (samples, drift(&starts, &poses), note)
}

/// `steps` steps of every world in `worlds`, the worlds cut into `threads` contiguous shares,
/// each stepped by a thread of its own (not a rayon task).
///
/// rapier3d built with its `parallel` feature waits inside its step for a rayon task of its
/// own (the deferred BVH optimisation, received from a channel; rapier issue #1008): with one
/// world per rayon task, every worker of a small pool can wait so at once, with nobody left
/// to run the tasks they wait for, and the run never ends (it hung on the 2-core build
/// machine and on a 16-core host). On threads outside the pool, a world's step hands its own
/// rayon work to the pool's idle workers. Without the feature each thread steps its own share
/// of the worlds, where rayon tasks would balance the shares by stealing: the same for a batch
/// of one scene, whose worlds cost alike.
fn step_rapier_worlds(worlds: &mut [RapierWorld], steps: usize, threads: usize) {
    let share = worlds.len().div_ceil(threads.max(1)).max(1);
    std::thread::scope(|s| {
        for part in worlds.chunks_mut(share) {
            s.spawn(move || {
                for _ in 0..steps {
                    for w in part.iter_mut() {
                        w.step();
                    }
                }
            });
        }
    });
}

fn main() {
    let args = Args::parse();
    if let Some(path) = &args.write_scene {
        let scene = scene_of("column20", 0);
        if let Some(dir) = std::path::Path::new(path).parent() {
            std::fs::create_dir_all(dir).expect("scene folder");
        }
        std::fs::write(path, scene.to_json()).expect("scene file");
        println!("wrote {path}");
        return;
    }
    for e in &args.engines {
        if !["gpu", "cpu", "rapier"].contains(&e.as_str()) {
            eprintln!("error: unknown engine {e:?} (gpu, cpu, rapier)");
            std::process::exit(2);
        }
    }
    let mut cases: Vec<(&str, usize)> = args.columns.iter().map(|&n| ("column20", n)).collect();
    cases.extend(args.pyramids.iter().map(|&n| ("pyramid", n)));
    let mut rows = Vec::new();
    for (case, worlds) in cases {
        let scene = scene_of(case, args.pyramid_height);
        let case_name = if case == "pyramid" {
            format!("pyramid{}", args.pyramid_height)
        } else {
            case.to_string()
        };
        let bodies = worlds * scene.bodies.len();
        let mut runs: Vec<(&str, bool)> = Vec::new();
        for e in &args.engines {
            runs.push((e.as_str(), false));
            if e == "gpu" && args.read_every_step {
                runs.push(("gpu", true));
            }
        }
        for (engine, every) in runs {
            if engine != "gpu" && worlds > args.cpu_max_worlds {
                continue;
            }
            let result = match engine {
                "gpu" => run_tumble(&args, &scene, worlds, Backend::Gpu, every),
                "cpu" => run_tumble(&args, &scene, worlds, Backend::Cpu, false),
                _ => Ok(run_rapier(&args, &scene, worlds)),
            };
            let name = match (engine, every) {
                ("gpu", true) => "tumble gpu, read every step".to_string(),
                ("rapier", _) => "rapier3d".to_string(),
                (e, _) => format!("tumble {e}"),
            };
            match result {
                Ok((samples, drift_m, note)) => {
                    let (median_ms, p90_ms) = median_p90(samples);
                    println!(
                        "{case_name:>10} x {worlds:>6}: {name:<28} {median_ms:>9.3} ms/step \
                         (p90 {p90_ms:.3}), {:>8.3} us/world-step, drift {:.2} mm; {note}",
                        median_ms * 1e3 / worlds as f64,
                        drift_m * 1e3
                    );
                    rows.push(Row {
                        case: case_name.clone(),
                        worlds,
                        bodies,
                        engine: name,
                        median_ms,
                        p90_ms,
                        drift_m,
                        note,
                    });
                }
                Err(e) => eprintln!("{case_name} x {worlds}: {name}: {e}"),
            }
        }
    }
    println!();
    println!(
        "| case | worlds | bodies | engine | ms per step (median) | p90 | us per world-step | \
         world-steps per s | x rapier3d | drift (mm) |"
    );
    println!("|---|---:|---:|---|---:|---:|---:|---:|---:|---:|");
    for r in &rows {
        let rapier = rows
            .iter()
            .find(|o| o.case == r.case && o.worlds == r.worlds && o.engine == "rapier3d");
        let ratio = rapier.map_or("-".to_string(), |o| {
            format!("{:.2}", o.median_ms / r.median_ms)
        });
        println!(
            "| {} | {} | {} | {} | {:.3} | {:.3} | {:.3} | {:.0} | {} | {:.2} |",
            r.case,
            r.worlds,
            r.bodies,
            r.engine,
            r.median_ms,
            r.p90_ms,
            r.median_ms * 1e3 / r.worlds as f64,
            r.worlds as f64 / (r.median_ms * 1e-3),
            ratio,
            r.drift_m * 1e3
        );
    }
    if let Some(path) = &args.csv {
        let mut out = String::from(
            "case,worlds,bodies,engine,median_ms,p90_ms,us_per_world_step,drift_m,note\n",
        );
        for r in &rows {
            out.push_str(&format!(
                "{},{},{},{},{:.6},{:.6},{:.4},{:.6},\"{}\"\n",
                r.case,
                r.worlds,
                r.bodies,
                r.engine,
                r.median_ms,
                r.p90_ms,
                r.median_ms * 1e3 / r.worlds as f64,
                r.drift_m,
                r.note
            ));
        }
        if let Some(dir) = std::path::Path::new(path).parent() {
            std::fs::create_dir_all(dir).expect("csv folder");
        }
        std::fs::write(path, out).expect("csv file");
        println!("wrote {path}");
    }
}
