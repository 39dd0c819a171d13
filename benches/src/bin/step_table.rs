//! Milliseconds per step for Tumble's backends and rapier3d, measured side by side in one run.
//!
//! ```sh
//! cargo run --release -p tumble-benches --features rapier-parallel --bin step_table -- \
//!     --scenes stack20,pyramid24,pyramid50 --steps 60
//! ```
//!
//! `--help` lists the flags and their defaults; an unknown flag or value is an error.
//!
//! Every engine runs the same `tumble-scenes` scene at the same time step and substep count.
//! A GPU or Hybrid row first steps a throwaway world of its scene for `--gpu-warmup-ms`, so
//! that the GPU is out of its idle clocks when the row's own world starts.
//! Each row reports the median and the 90th percentile of the wall time of `step()` after a
//! warm-up, and the largest horizontal drift of any dynamic body at the end, so that a faster
//! row can be checked for holding its stack just as well. GPU rows include the GPU work: a
//! step's poses are read back before the clock stops. Tumble's rows also note each stage's
//! mean time over the timed steps (`StepStats::timings`) and a hash of the final poses' bits,
//! so that two builds can be checked for computing the same step.

use std::time::Instant;

use clap::{Parser, ValueEnum};
use tumble::EffectOverrides;
use tumble::prelude::*;
use tumble_benches::cli::{SceneName, count};
use tumble_scenes::{RapierOptions, Scene, build_rapier_with};
use tumble_solver::{FrictionPasses, SolveKernel, Stage};

/// Steps run before timing starts: pipelines compile, buffers grow, caches warm up.
const WARMUP_STEPS: usize = 10;

/// Milliseconds per step for Tumble's backends and rapier3d, side by side.
#[derive(Parser, Debug)]
struct Args {
    /// Scenes, comma-separated: stackN, pyramidH or poolN.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "stack20,pyramid24,pyramid50"
    )]
    scenes: Vec<SceneName>,
    /// Engines, comma-separated, one row each.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "gpu,hybrid,cpu,rapier"
    )]
    backends: Vec<Engine>,
    /// Timed steps per row (after the warm-up steps).
    #[arg(long, default_value_t = 60, value_parser = count())]
    steps: usize,
    /// Substeps of Tumble's soft step, and rapier's solver iterations.
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..))]
    substeps: u32,
    /// Biased passes per substep of Tumble's soft step (`SolverConfig::iterations`; rapier3d
    /// is not affected).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    iterations: u32,
    /// The order of Tumble's CPU solver (the CPU and Hybrid rows): `colored` (the greedy
    /// top-down coloring, the default) or `rounds` (the GPU's coloring algorithm,
    /// `SolveOrder::ColoredInRounds`).
    #[arg(long, value_enum, default_value_t = Order::Colored)]
    order: Order,
    /// Before each GPU or Hybrid row, a separate world of the same scene steps for this many
    /// milliseconds (0: none), so that the GPU has left its idle clocks when the row starts:
    /// an H100 idles at 345 of its 1,980 MHz, and rows that started there measured up to
    /// three times their later time. The measured world, its steps and its pose hash are the
    /// same either way.
    #[arg(long, default_value_t = 500)]
    gpu_warmup_ms: u64,
}

/// Tumble's CPU solve order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Order {
    /// `SolveOrder::Colored`: greedy coloring, top of a pile first.
    Colored,
    /// `SolveOrder::ColoredInRounds`: the GPU's parallel rounds under hashed priorities.
    Rounds,
}

/// An engine of a row: one of Tumble's backends, or rapier3d.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Engine {
    /// Tumble, every stage on the CPU.
    Cpu,
    /// Tumble on the CPU with the scalar solve kernel (one constraint at a time,
    /// `SolveKernel::Scalar`) instead of the lanes: the same bits, the reference's time.
    CpuScalar,
    /// Tumble on the CPU with contact recycling off (`WorldConfig::recycle_distance = 0`):
    /// every manifold computed afresh every step, the step before recycling.
    CpuFresh,
    /// Tumble on the CPU with friction in the relax passes only
    /// (`SolverConfig::friction_passes = FrictionPasses::RelaxOnly`).
    CpuRelaxFriction,
    /// Tumble, every stage on the GPU.
    Gpu,
    /// Tumble on the GPU with friction in the relax passes only.
    GpuRelaxFriction,
    /// Tumble on the GPU with contact recycling off: every manifold computed afresh every
    /// step, the GPU step before recycling.
    GpuFresh,
    /// Tumble, collision on the GPU and the solver on the CPU.
    Hybrid,
    /// rapier3d.
    Rapier,
}

impl Engine {
    /// Tumble's backend, or `None` for rapier3d.
    fn backend(self) -> Option<Backend> {
        match self {
            Engine::Cpu | Engine::CpuScalar | Engine::CpuFresh | Engine::CpuRelaxFriction => {
                Some(Backend::Cpu)
            }
            Engine::Gpu | Engine::GpuRelaxFriction | Engine::GpuFresh => Some(Backend::Gpu),
            Engine::Hybrid => Some(Backend::Hybrid),
            Engine::Rapier => None,
        }
    }

    /// The solve kernel of a Tumble row.
    fn kernel(self) -> SolveKernel {
        match self {
            Engine::CpuScalar => SolveKernel::Scalar,
            _ => SolveKernel::Lanes,
        }
    }

    /// Which passes of a Tumble row solve friction.
    fn friction_passes(self) -> FrictionPasses {
        match self {
            Engine::CpuRelaxFriction | Engine::GpuRelaxFriction => FrictionPasses::RelaxOnly,
            _ => FrictionPasses::Every,
        }
    }

    /// The contact recycle distance of a Tumble row.
    fn recycle_distance(self) -> f32 {
        match self {
            Engine::CpuFresh | Engine::GpuFresh => 0.0,
            _ => tumble_solver::DEFAULT_RECYCLE_DISTANCE,
        }
    }

    /// The name the row is labelled with, as given on the command line.
    fn name(self) -> &'static str {
        match self {
            Engine::Cpu => "cpu",
            Engine::CpuScalar => "cpu-scalar",
            Engine::CpuFresh => "cpu-fresh",
            Engine::CpuRelaxFriction => "cpu-relax-friction",
            Engine::Gpu => "gpu",
            Engine::GpuRelaxFriction => "gpu-relax-friction",
            Engine::GpuFresh => "gpu-fresh",
            Engine::Hybrid => "hybrid",
            Engine::Rapier => "rapier",
        }
    }
}

/// One timed run: per-step wall times in ms and the final horizontal drift in m.
struct Run {
    ms: Vec<f64>,
    drift: f32,
    note: String,
}

fn horizontal_drift(scene: &Scene, poses: &[([f32; 3], bool)]) -> f32 {
    scene
        .bodies
        .iter()
        .zip(poses)
        .filter(|(_, (_, dynamic))| *dynamic)
        .map(|(spec, (p, _))| {
            let dx = p[0] - spec.position[0];
            let dz = p[2] - spec.position[2];
            (dx * dx + dz * dz).sqrt()
        })
        .fold(0.0, f32::max)
}

fn run_tumble(scene: &Scene, backend: Backend, engine: Engine, args: &Args) -> Result<Run, Error> {
    let (order, steps, gpu_warmup_ms) = (args.order, args.steps, args.gpu_warmup_ms);
    let solver = SolverConfig {
        substeps: args.substeps,
        iterations: args.iterations,
        kernel: engine.kernel(),
        friction_passes: engine.friction_passes(),
        order: match order {
            Order::Colored => SolveOrder::Colored,
            Order::Rounds => SolveOrder::ColoredInRounds,
        },
        ..SolverConfig::default()
    };
    let config = WorldConfig {
        backend,
        solver,
        // The full step's cost: no body is put to sleep.
        effects: EffectOverrides::NO_SLEEP,
        recycle_distance: engine.recycle_distance(),
        ..WorldConfig::default()
    };
    if backend != Backend::Cpu && gpu_warmup_ms > 0 {
        // A throwaway world: the clocks come up, the measured world's steps stay the same.
        let (mut warm, handles) = World::from_scene(scene, config)?;
        let start = Instant::now();
        while start.elapsed().as_millis() < u128::from(gpu_warmup_ms) {
            warm.step()?;
            warm.pose(handles[handles.len() - 1])?;
        }
    }
    let (mut world, handles) = World::from_scene(scene, config)?;
    let mut ms = Vec::with_capacity(steps);
    // Each stage's time summed over the timed steps (one step's reading is noisy).
    let mut stage_sum = [std::time::Duration::ZERO; Stage::ALL.len()];
    for i in 0..WARMUP_STEPS + steps {
        let t0 = Instant::now();
        world.step()?;
        // Reading one pose forces the step's results back to the host on GPU backends.
        world.pose(handles[handles.len() - 1])?;
        if i >= WARMUP_STEPS {
            ms.push(t0.elapsed().as_secs_f64() * 1e3);
            let timings = world.stats().timings;
            for (sum, (_, d)) in stage_sum.iter_mut().zip(timings.iter()) {
                *sum += d;
            }
        }
    }
    let poses = handles
        .iter()
        .map(|&h| {
            let p = world.pose(h)?.translation.vector;
            Ok(([p.x, p.y, p.z], world.kind(h)? == BodyKind::Dynamic))
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let hash = pose_hash(&world, &handles)?;
    let stats = world.stats();
    let stage_ms: Vec<String> = Stage::ALL
        .iter()
        .zip(&stage_sum)
        .map(|(s, d)| format!("{} {:.2}", s.name(), d.as_secs_f64() * 1e3 / steps as f64))
        .collect();
    let note = format!(
        "{} pairs, {} contacts, {} of {} manifolds recycled, {} colors; pose hash {hash:#018x}; mean stage ms: {}",
        stats.pairs,
        stats.contact_points,
        stats.recycled_manifolds,
        stats.manifolds,
        stats.colors,
        stage_ms.join(" ")
    );
    Ok(Run {
        ms,
        drift: horizontal_drift(scene, &poses),
        note,
    })
}

/// FNV-1a over the bits of every body's final position and rotation, in handle order: two
/// builds that compute the same bits print the same hash (`tests/tests/golden_hash.rs` hashes
/// the same way).
fn pose_hash(world: &World, handles: &[BodyHandle]) -> Result<u64, Error> {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let mut hash = OFFSET;
    for &h in handles {
        let pose = world.pose(h)?;
        let q = pose.rotation.quaternion();
        let v = pose.translation.vector;
        for c in [v.x, v.y, v.z, q.i, q.j, q.k, q.w] {
            for byte in c.to_bits().to_le_bytes() {
                hash ^= u64::from(byte);
                hash = hash.wrapping_mul(PRIME);
            }
        }
    }
    Ok(hash)
}

fn run_rapier(scene: &Scene, substeps: u32, steps: usize) -> Run {
    let options = RapierOptions {
        solver_iterations: substeps as usize,
        ..RapierOptions::default()
    };
    let mut world = build_rapier_with(scene, &options);
    let mut ms = Vec::with_capacity(steps);
    for i in 0..WARMUP_STEPS + steps {
        let t0 = Instant::now();
        world.step();
        if i >= WARMUP_STEPS {
            ms.push(t0.elapsed().as_secs_f64() * 1e3);
        }
    }
    let poses: Vec<_> = world
        .body_poses()
        .into_iter()
        .zip(&scene.bodies)
        .map(|((p, _), spec)| (p, spec.is_dynamic()))
        .collect();
    let threads = if cfg!(feature = "rapier-parallel") {
        format!(
            // rapier3d's `parallel` feature runs on rayon's global pool, which follows
            // `RAYON_NUM_THREADS` (the machine's threads otherwise), like Tumble's rows.
            "parallel, {} threads",
            rayon::current_num_threads()
        )
    } else {
        "one thread".to_owned()
    };
    Run {
        ms,
        drift: horizontal_drift(scene, &poses),
        note: threads,
    }
}

fn percentile(sorted: &[f64], q: f64) -> f64 {
    let i = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted[i]
}

fn main() {
    let args = Args::parse();
    println!(
        "| scene | bodies | engine | median ms/step | p90 ms/step | max drift (mm) | vs rapier | notes |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for name in &args.scenes {
        let scene = name.build();
        let mut rows = Vec::new();
        for &engine in &args.backends {
            let run = match engine.backend() {
                Some(backend) => run_tumble(&scene, backend, engine, &args),
                None => Ok(run_rapier(&scene, args.substeps, args.steps)),
            };
            rows.push((engine.name(), run));
        }
        let median_of = |run: &Run| {
            let mut ms = run.ms.clone();
            ms.sort_by(f64::total_cmp);
            (percentile(&ms, 0.5), percentile(&ms, 0.9))
        };
        let rapier_median = rows
            .iter()
            .find(|(b, _)| *b == Engine::Rapier.name())
            .and_then(|(_, r)| r.as_ref().ok())
            .map(|r| median_of(r).0);
        for (backend, run) in &rows {
            match run {
                Ok(run) => {
                    let (median, p90) = median_of(run);
                    let ratio = rapier_median
                        .map(|r| format!("{:.2}x faster", r / median))
                        .unwrap_or_default();
                    println!(
                        "| {name} | {} | {backend} | {median:.3} | {p90:.3} | {:.2} | {ratio} | {} |",
                        scene.bodies.len(),
                        run.drift * 1e3,
                        run.note
                    );
                }
                Err(e) => println!(
                    "| {name} | {} | {backend} | - | - | - | - | {e} |",
                    scene.bodies.len()
                ),
            }
        }
    }
}
