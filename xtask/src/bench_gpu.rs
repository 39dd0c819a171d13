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

/// The scenes of a default run, in order.
const DEFAULT_SCENES: &[&str] = &[
    "stack20",
    "pyramid24",
    "pyramid50",
    "pyramid100",
    "nexus_pyramid50",
    "pool1000000",
];
/// The scenes of `--quick`: small enough for a software rasterizer in a few minutes.
const QUICK_SCENES: &[&str] = &["stack20", "pyramid8", "pool10000"];
/// Warm-up steps before timing starts (pipelines compile, buffers grow, caches warm up),
/// fewer when the budget of a run says so.
const WARMUP_STEPS: usize = 10;
/// The fewest timed steps of a run, whatever its budget.
const MIN_TIMED_STEPS: usize = 5;
/// Steps of the timestamped GPU run before its profiled steps, and the profiled steps.
const PROFILE_SETTLE_STEPS: usize = 10;
const PROFILE_STEPS: usize = 10;
/// The fewest profiled steps, whatever the budget.
const MIN_PROFILED_STEPS: usize = 3;
/// Layers of the generated box pool: columns of this many unit cubes resting on the floor.
const POOL_LAYERS: usize = 16;
/// Horizontal gap between neighbouring columns of the pool, as between the cubes of a
/// pyramid's layer (`tumble_scenes::builders::common::LAYER_GAP`).
const POOL_GAP: f32 = builders::common::LAYER_GAP;

/// Options of `cargo xtask bench-gpu`.
#[derive(Args, Debug)]
pub struct BenchGpuArgs {
    /// Scenes, comma-separated: stackN, pyramidH (packed, tumble-scenes' builder), poolN (N
    /// unit cubes in columns of 16 on a floor), nexus_pyramidH [default: stack20, pyramid24,
    /// pyramid50, pyramid100, nexus_pyramid50, pool1000000; with --quick: stack20, pyramid8,
    /// pool10000].
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

/// An engine of a row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Engine {
    Tumble(Backend),
    Rapier,
}

impl Engine {
    fn parse(name: &str) -> Result<Self, String> {
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

    fn name(self) -> &'static str {
        match self {
            Self::Tumble(Backend::Gpu) => "tumble-gpu",
            Self::Tumble(Backend::Cpu) => "tumble-cpu",
            Self::Tumble(Backend::Hybrid) => "tumble-hybrid",
            Self::Rapier => "rapier3d",
        }
    }
}

/// A scene of the benchmark, or why it cannot be built.
fn scene_named(name: &str) -> Result<Scene, String> {
    let number = |rest: &str| {
        rest.replace('_', "")
            .parse::<usize>()
            .map_err(|_| format!("scene {name:?}: expected a number after the kind"))
    };
    if let Some(h) = name.strip_prefix("nexus_pyramid") {
        number(h)?;
        return Err(format!(
            "no builder for nexus's spaced dropped pyramid in tumble-scenes; {name} is skipped"
        ));
    }
    if let Some(n) = name.strip_prefix("stack") {
        return Ok(builders::stack(number(n)?));
    }
    if let Some(h) = name.strip_prefix("pyramid") {
        return Ok(builders::pyramid(number(h)?));
    }
    if let Some(n) = name.strip_prefix("pool") {
        return Ok(box_pool(number(n)?));
    }
    Err(format!(
        "unknown scene {name:?}: stackN, pyramidH, poolN or nexus_pyramidH"
    ))
}

/// `n` unit cubes at rest on a fixed floor, in square columns of [`POOL_LAYERS`] cubes (the top
/// layer partly filled), neighbouring columns [`POOL_GAP`] apart and each cube exactly on the
/// one below: every cube is in contact from the first step.
pub fn box_pool(n: usize) -> Scene {
    let per_layer = n.div_ceil(POOL_LAYERS).max(1);
    let side = (per_layer as f64).sqrt().ceil() as usize;
    let half = builders::common::UNIT_HALF;
    let pitch = 2.0 * half + POOL_GAP;
    let floor_half = 0.5 * side as f32 * pitch + 2.0;
    let mut scene = Scene::new(
        format!("pool_{n}"),
        format!(
            "{n} unit cubes at rest in columns of {POOL_LAYERS} on a floor, {side} x {side} columns."
        ),
    );
    scene.bodies.push(BodySpec::fixed(
        [floor_half, 0.5, floor_half],
        [0.0, -0.5, 0.0],
    ));
    let first = -(side as f32 - 1.0) * 0.5 * pitch;
    for i in 0..n {
        let layer = i / (side * side);
        let row = (i / side) % side;
        let col = i % side;
        scene.bodies.push(builders::common::unit_cube([
            first + col as f32 * pitch,
            half + layer as f32 * 2.0 * half,
            first + row as f32 * pitch,
        ]));
    }
    scene
}

/// The scene's up axis: against gravity (y when there is none).
fn up_axis(scene: &Scene) -> [f32; 3] {
    let [x, y, z] = scene.gravity;
    let norm = (x * x + y * y + z * z).sqrt();
    if norm > 0.0 {
        [-x / norm, -y / norm, -z / norm]
    } else {
        [0.0, 1.0, 0.0]
    }
}

/// Largest horizontal displacement of a dynamic body from where the scene put it, and the
/// lowest dynamic body's centre along the up axis, in meters.
fn drift_and_lowest(scene: &Scene, positions: &[[f32; 3]]) -> (f64, f64) {
    let up = up_axis(scene);
    let dot = |a: [f32; 3], b: [f32; 3]| {
        f64::from(a[0]) * f64::from(b[0])
            + f64::from(a[1]) * f64::from(b[1])
            + f64::from(a[2]) * f64::from(b[2])
    };
    let mut drift: f64 = 0.0;
    let mut lowest = f64::INFINITY;
    for (spec, &p) in scene.bodies.iter().zip(positions) {
        if !spec.is_dynamic() {
            continue;
        }
        let d = [
            p[0] - spec.position[0],
            p[1] - spec.position[1],
            p[2] - spec.position[2],
        ];
        let along = dot(d, up);
        let total = dot(d, d);
        drift = drift.max((total - along * along).max(0.0).sqrt());
        lowest = lowest.min(dot(p, up));
    }
    (drift, lowest)
}

/// The steps of one run: warm-up until [`WARMUP_STEPS`] or a quarter of the budget, then timed
/// steps until `steps` or the budget (at least [`MIN_TIMED_STEPS`]). Returns the timed steps'
/// wall times in ms and a note when the budget cut the run short.
fn timed_steps(
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
fn run_engine(scene: &Scene, engine: Engine, args: &BenchGpuArgs, steps: usize) -> Row {
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
struct RunResult {
    ms: Vec<f64>,
    positions: Vec<[f32; 3]>,
    note: String,
}

fn run_tumble(
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
        ..WorldConfig::default()
    };
    let (mut world, handles) = World::from_scene(scene, config).map_err(|e| e.to_string())?;
    let last = *handles.last().ok_or("the scene has no bodies")?;
    let (ms, note) = timed_steps(steps, budget, || {
        world.step().map_err(|e| e.to_string())?;
        // Reading one pose forces the step's results back to the host on GPU backends.
        world.pose(last).map(|_| ()).map_err(|e| e.to_string())
    })?;
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

fn run_rapier(scene: &Scene, substeps: u32, steps: usize, budget: Duration) -> RunResult {
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
fn rapier_threads() -> String {
    if cfg!(feature = "rapier-parallel") {
        format!(
            "parallel, {} threads",
            std::thread::available_parallelism().map_or(1, |n| n.get())
        )
    } else {
        "one thread (built without the rapier-parallel feature)".to_owned()
    }
}

/// What the timestamped GPU run adds to the GPU row.
struct GpuProfile {
    /// GPU time per step of each pass name, ms, and how many passes of that name a step has.
    passes: Vec<(&'static str, f64, usize)>,
    traffic: TrafficCounts,
    buffer_bytes: u64,
}

/// Steps `scene` on a [`GpuWorld`] with timestamps, as the facade's GPU backend does, and
/// returns the per-pass times (empty without timestamp queries), the counts of the traffic
/// model and the world's buffer bytes.
fn profile_gpu(
    ctx: &GpuContext,
    scene: &Scene,
    substeps: u32,
    budget: Duration,
) -> Result<GpuProfile, String> {
    let err = |e: tumble_gpu::GpuError| e.to_string();
    let (bodies, states) = tumble_tests::scene_support::bodies_of(scene);
    let defaults = WorldConfig::default();
    let mut world = GpuWorld::new(
        ctx,
        GpuWorldConfig {
            gravity: Vec3::from(scene.gravity),
            dt: scene.dt,
            margin: defaults.margin,
            solver: SolverConfig {
                substeps,
                ..defaults.solver
            },
            timestamps: true,
            ..Default::default()
        },
    )
    .map_err(err)?;
    world.set_bodies(&bodies, &states).map_err(err)?;
    // Settling and profiled steps, fewer where a step is slow (as `timed_steps` does).
    let start = Instant::now();
    let mut last = Duration::ZERO;
    let mut settled = 0;
    while settled < PROFILE_SETTLE_STEPS && (settled < 2 || start.elapsed() < budget / 4) {
        let t0 = Instant::now();
        world.step().map_err(err)?;
        // Each step's timestamps are read, as in the profiled steps.
        world.timings().map_err(err)?;
        last = t0.elapsed();
        settled += 1;
    }
    let left = budget.saturating_sub(start.elapsed());
    let affordable = (left.as_secs_f64() / last.as_secs_f64().max(1e-6)) as usize;
    let profiled = PROFILE_STEPS.min(affordable.max(MIN_PROFILED_STEPS));
    let mut sums: BTreeMap<&'static str, (f64, usize)> = BTreeMap::new();
    for _ in 0..profiled {
        world.step().map_err(err)?;
        for (name, seconds) in world.timings().map_err(err)? {
            let e = sums.entry(name).or_default();
            e.0 += seconds;
            e.1 += 1;
        }
    }
    let snapshot = world
        .read_now(ReadRequest {
            contacts: true,
            ..Default::default()
        })
        .map_err(err)?;
    let (manifolds, points) = snapshot.contacts.as_ref().map_or((0, 0), |c| {
        let live = c.manifolds.iter().filter(|m| m.len > 0);
        (
            live.clone().count() as u64,
            live.map(|m| u64::from(m.len)).sum::<u64>(),
        )
    });
    let mut passes: Vec<_> = sums
        .into_iter()
        .map(|(name, (seconds, count))| (name, seconds * 1e3 / profiled as f64, count / profiled))
        .collect();
    passes.sort_by(|a, b| b.1.total_cmp(&a.1));
    Ok(GpuProfile {
        passes,
        traffic: TrafficCounts {
            bodies: bodies.len() as u64,
            manifolds,
            points,
            substeps: u64::from(substeps),
        },
        buffer_bytes: world.buffer_bytes(),
    })
}

/// The line a profile process prints its result on.
const PROFILE_PREFIX: &str = "bench-gpu profile: ";

/// Runs [`profile_gpu`] on `name` in this process (a fresh device) and prints the result.
fn print_profile(name: &str, substeps: u32, budget: Duration) -> Result<bool, String> {
    let scene = scene_named(name)?;
    let ctx = GpuContext::new().map_err(|e| format!("no GPU adapter: {e}"))?;
    let p = profile_gpu(&ctx, &scene, substeps, budget)?;
    let passes: Vec<_> = p
        .passes
        .iter()
        .map(|(name, ms, count)| serde_json::json!([name, ms, count]))
        .collect();
    let value = serde_json::json!({
        "passes": passes,
        "bodies": p.traffic.bodies,
        "manifolds": p.traffic.manifolds,
        "points": p.traffic.points,
        "substeps": p.traffic.substeps,
        "buffer_bytes": p.buffer_bytes,
    });
    println!("{PROFILE_PREFIX}{value}");
    Ok(true)
}

/// What a profile process of the same binary measured on `name`.
fn profile_in_child(name: &str, substeps: u32, budget_s: f64) -> Result<ChildProfile, String> {
    let exe = std::env::current_exe().map_err(|e| format!("finding this binary: {e}"))?;
    let output = std::process::Command::new(exe)
        .args(["bench-gpu", "--profile-scene", name, "--substeps"])
        .arg(substeps.to_string())
        .arg("--budget-s")
        .arg(budget_s.to_string())
        .output()
        .map_err(|e| format!("starting the profile process: {e}"))?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    let Some(line) = stdout.lines().find_map(|l| l.strip_prefix(PROFILE_PREFIX)) else {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let last = stderr
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("");
        return Err(format!(
            "the profile process failed ({}): {last}",
            output.status
        ));
    };
    let v: serde_json::Value = serde_json::from_str(line).map_err(|e| e.to_string())?;
    let count = |key: &str| v[key].as_u64().unwrap_or(0);
    let passes = v["passes"]
        .as_array()
        .map(|list| {
            list.iter()
                .map(|p| {
                    (
                        p[0].as_str().unwrap_or("?").to_owned(),
                        p[1].as_f64().unwrap_or(0.0),
                        p[2].as_u64().unwrap_or(0) as usize,
                    )
                })
                .collect()
        })
        .unwrap_or_default();
    Ok(ChildProfile {
        passes,
        traffic: TrafficCounts {
            bodies: count("bodies"),
            manifolds: count("manifolds"),
            points: count("points"),
            substeps: count("substeps"),
        },
        buffer_bytes: count("buffer_bytes"),
    })
}

/// [`GpuProfile`] as read back from a profile process.
struct ChildProfile {
    passes: Vec<(String, f64, usize)>,
    traffic: TrafficCounts,
    buffer_bytes: u64,
}

/// Writes the scenes as JSON (tumble-scenes' schema, compact) into `dir`.
fn write_scenes(dir: &std::path::Path, names: &[String]) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("creating {}: {e}", dir.display()))?;
    for name in names {
        match scene_named(name) {
            Ok(scene) => {
                let path = dir.join(format!("{name}.json"));
                let text = serde_json::to_string(&scene).map_err(|e| e.to_string())?;
                std::fs::write(&path, text)
                    .map_err(|e| format!("writing {}: {e}", path.display()))?;
                println!("wrote {} ({} bodies)", path.display(), scene.bodies.len());
            }
            Err(e) => println!("{name}: {e}"),
        }
    }
    Ok(())
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
    fn scene_names_give_the_benchmark_sizes() {
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
