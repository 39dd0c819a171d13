//! How the GPU solve's time splits between a fixed cost per dispatch and a cost per
//! constraint: per-pass GPU times (timestamp queries) of `GpuWorld` on the wide path, for
//! pyramids of several sizes and several sweep counts.
//!
//! ```sh
//! cargo run --release -p tumble-benches --bin dispatch_probe -- 4,12,24,50 1,4 wide,fused all,in-use per-body,by-color per-color,one
//! ```
//!
//! `--help` lists the arguments and their values; an unknown value is an error. The first
//! argument lists pyramid heights, the second biased iterations per substep (one
//! relax iteration each, 4 substeps), the third the solver paths (`wide`, `fused`), the
//! fourth how many colors the wide path dispatches one by one (`all` 24, `in-use` as many as
//! a recent step used; the default), the fifth how the warm start visits the colors
//! (`per-body`, one dispatch and one for the overflow set, the default; `by-color`, one per
//! color as the other passes), the sixth how the wide path dispatches its substeps
//! (`per-color`, a dispatch per phase; `one`, every substep in one `solve_step` dispatch with
//! the workgroups it picks; `one:N`, with N workgroups; the default `auto`, as the world
//! picks for the device). Each scene settles for 30 steps, then 10 are profiled.
//! The solve pass records `4 * (2 + (K + 1) * (2 + iterations))` dispatches for K colors
//! dispatched one by one with the colored warm start (each pass closes with one dispatch for
//! the colors beyond K and the overflow set), and `4 * (4 + (K + 1) * (1 + iterations))` with
//! the per-body one, so a solve time that hardly grows from the smallest pyramid to the largest
//! is the cost of the dispatches and their barriers, and the growth with the height is the
//! cost of the constraints. The last column hashes every pose and velocity after the
//! profiled steps, so two builds or settings meant to compute the same result can be
//! compared bit for bit. `--no-immediates` opens the device without immediate data, for the
//! wide path's fallback (a bind group per color) on an adapter that has it.

use std::collections::BTreeMap;

use clap::{Parser, ValueEnum};

use tumble_benches::gpu_pool::contact_counts;
use tumble_gpu::solver::{SolvePath, SubstepDispatch, WarmStartSweep};
use tumble_gpu::step::{ColorDispatch, GpuWorldConfig, PathPolicy, ReadRequest};
use tumble_gpu::{GpuContext, GpuOptions};
use tumble_solver::SolverConfig;
use tumble_tests::scene_support::gpu_world_of;

/// Steps before profiling.
const SETTLE_STEPS: usize = 30;
/// Steps profiled.
const PROFILED_STEPS: usize = 10;
/// Substeps per step, as in the speed targets.
const SUBSTEPS: u32 = 4;

/// A solver path to probe.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum PathArg {
    /// One dispatch per color and pass.
    Wide,
    /// One single-workgroup dispatch.
    Fused,
}

/// How many colors the wide path dispatches one by one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum ColorsArg {
    /// All 24.
    All,
    /// As many as a recent step used (the default).
    InUse,
}

/// How the wide path's warm start visits the colors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum WarmStartArg {
    /// One dispatch, one thread per body (and one for the overflow set).
    PerBody,
    /// One dispatch per color.
    ByColor,
}

/// Per-pass GPU times of the wide and fused solver paths on pyramids (arguments are
/// positional, each a comma-separated list).
#[derive(Parser, Debug)]
struct Args {
    /// Pyramid heights.
    #[arg(action = clap::ArgAction::Set, num_args = 1, value_delimiter = ',', default_value = "4,12,24,50", value_parser = clap::value_parser!(u32).range(1..))]
    heights: Vec<u32>,
    /// Biased iterations per substep (one relax iteration each, 4 substeps).
    #[arg(action = clap::ArgAction::Set, num_args = 1, value_delimiter = ',', default_value = "1,4", value_parser = clap::value_parser!(u32).range(1..))]
    iterations: Vec<u32>,
    /// Solver paths.
    #[arg(
        action = clap::ArgAction::Set,
        num_args = 1,
        value_enum,
        value_delimiter = ',',
        default_value = "wide"
    )]
    paths: Vec<PathArg>,
    /// Colors the wide path dispatches one by one.
    #[arg(
        action = clap::ArgAction::Set,
        num_args = 1,
        value_enum,
        value_delimiter = ',',
        default_value = "in-use"
    )]
    colors: Vec<ColorsArg>,
    /// Warm starts of the wide path.
    #[arg(
        action = clap::ArgAction::Set,
        num_args = 1,
        value_enum,
        value_delimiter = ',',
        default_value = "per-body"
    )]
    warm_starts: Vec<WarmStartArg>,
    /// How the wide path dispatches its substeps: `auto`, `per-color`, `one` or `one:N`.
    #[arg(
        action = clap::ArgAction::Set,
        num_args = 1,
        value_delimiter = ',',
        default_value = "auto",
        value_parser = parse_substeps
    )]
    substeps: Vec<SubstepDispatch>,
    /// Open the device without immediate data, so the wide path binds a uniform per color
    /// (`solve_color`) even where the adapter has it.
    #[arg(long)]
    no_immediates: bool,
}

/// A [`SubstepDispatch`] from `auto`, `per-color`, `one` or `one:N` (N workgroups, at least 1).
fn parse_substeps(text: &str) -> Result<SubstepDispatch, String> {
    match text {
        "auto" => Ok(SubstepDispatch::Auto),
        "per-color" => Ok(SubstepDispatch::PerColor),
        "one" => Ok(SubstepDispatch::OneDispatch { groups: None }),
        _ => match text.strip_prefix("one:").map(str::parse::<u32>) {
            Some(Ok(groups)) if groups >= 1 => Ok(SubstepDispatch::OneDispatch {
                groups: Some(groups),
            }),
            _ => Err(format!(
                "substep dispatch {text:?}: expected auto, per-color, one or one:N with N >= 1"
            )),
        },
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let heights = args.heights;
    let iterations = args.iterations;
    let paths: Vec<SolvePath> = args
        .paths
        .iter()
        .map(|p| match p {
            PathArg::Wide => SolvePath::Wide,
            PathArg::Fused => SolvePath::Fused,
        })
        .collect();
    let dispatch_modes: Vec<ColorDispatch> = args
        .colors
        .iter()
        .map(|c| match c {
            ColorsArg::All => ColorDispatch::All,
            ColorsArg::InUse => ColorDispatch::InUse,
        })
        .collect();
    let warm_starts: Vec<WarmStartSweep> = args
        .warm_starts
        .iter()
        .map(|w| match w {
            WarmStartArg::PerBody => WarmStartSweep::PerBody,
            WarmStartArg::ByColor => WarmStartSweep::ByColor,
        })
        .collect();
    let mut ctx = GpuContext::new()?;
    if args.no_immediates {
        ctx = GpuContext::with_options(&GpuOptions {
            adapter_name: Some(ctx.info.name.clone()),
            timestamps: ctx.has_timestamps,
            limits: Some(tumble_gpu::wgpu::Limits {
                max_immediate_size: 0,
                ..ctx.adapter.limits()
            }),
        })?;
    }
    println!(
        "device: {} ({:?}), immediate data: {}",
        ctx.info.name, ctx.info.backend, ctx.has_immediates
    );
    println!(
        "| height | bodies | manifolds | iterations | path | warm start | colors dispatched | solve dispatches | solve ms | per dispatch us | prepare ms | color ms | solver stages ms | collision ms | GPU total ms | pose bits |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &h in &heights {
        let scene = tumble_scenes::pyramid(h as usize);
        let bodies = scene.bodies.len();
        let mut settings = Vec::new();
        for &i in &iterations {
            for &p in &paths {
                for &m in &dispatch_modes {
                    for &w in &warm_starts {
                        settings.extend(args.substeps.iter().map(|&d| (i, p, m, w, d)));
                    }
                }
            }
        }
        for (iters, path, color_dispatch, warm_start_sweep, substep_dispatch) in settings {
            let mut world = gpu_world_of(
                &ctx,
                &scene,
                GpuWorldConfig {
                    timestamps: true,
                    path: PathPolicy::Always(path),
                    color_dispatch,
                    warm_start_sweep,
                    substep_dispatch,
                    solver: SolverConfig {
                        substeps: SUBSTEPS,
                        iterations: iters,
                        relax_iterations: 1,
                        ..Default::default()
                    },
                    ..Default::default()
                },
            )?;
            for _ in 0..SETTLE_STEPS {
                world.step()?;
            }
            ctx.wait_idle()?;
            let mut sums: BTreeMap<&'static str, f64> = BTreeMap::new();
            for _ in 0..PROFILED_STEPS {
                world.step()?;
                for (name, seconds) in world.timings()? {
                    *sums.entry(name).or_default() += seconds / PROFILED_STEPS as f64;
                }
            }
            let (manifolds, _) = contact_counts(&mut world)?;
            let bits = pose_bits(&mut world)?;
            let ms = |name: &str| sums.get(name).copied().unwrap_or(0.0) * 1e3;
            let total: f64 = sums.values().sum::<f64>() * 1e3;
            let solver: f64 = ["color", "prepare", "solve", "finish"]
                .iter()
                .map(|n| ms(n))
                .sum();
            let colors = world.solver().color_dispatches();
            let per_body = warm_start_sweep.per_body(ctx.info.device_type);
            let one_dispatch = world.solver().substep_groups(bodies as u32);
            let dispatches = match (path, per_body) {
                (SolvePath::Wide, _) if one_dispatch.is_some() => 1,
                (SolvePath::Wide, false) => SUBSTEPS * (2 + (colors + 1) * (2 + iters)),
                (SolvePath::Wide, true) => SUBSTEPS * (4 + (colors + 1) * (1 + iters)),
                (SolvePath::Fused | SolvePath::Worlds, _) => 1,
            };
            println!(
                "| {h} | {} | {manifolds} | {iters} | {path:?}{} | {warm_start_sweep:?} | {colors} | {dispatches} | {:.3} | {:.1} | {:.3} | {:.3} | {solver:.3} | {:.3} | {total:.3} | {bits:016x} |",
                bodies,
                one_dispatch.map_or(String::new(), |g| format!(" (one dispatch, {g} groups)")),
                ms("solve") + ms("solve_fused"),
                (ms("solve") + ms("solve_fused")) * 1e3 / f64::from(dispatches),
                ms("prepare"),
                ms("color"),
                total - solver,
            );
        }
    }
    for &mode in &dispatch_modes {
        for &substeps in &args.substeps {
            host_times(&ctx, &heights, mode, substeps)?;
        }
    }
    Ok(())
}

/// A hash of the bits of every pose and velocity after the profiled steps: builds that should
/// compute the same result (a faster kernel) must print the same value.
fn pose_bits(world: &mut tumble_gpu::step::GpuWorld) -> Result<u64, Box<dyn std::error::Error>> {
    let snapshot = world.read_now(ReadRequest {
        poses: true,
        velocities: true,
        ..Default::default()
    })?;
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    let words = snapshot
        .poses
        .iter()
        .flat_map(|p| p.position.into_iter().chain(p.rotation))
        .chain(
            snapshot
                .velocities
                .iter()
                .flat_map(|v| v.linear.into_iter().chain(v.angular)),
        );
    for word in words {
        hash = (hash ^ u64::from(word.to_bits())).wrapping_mul(0x0000_0100_0000_01b3);
    }
    Ok(hash)
}

/// Where a step's wall time goes on the host, timestamps off, default path choice (and the
/// substeps dispatched as `substep_dispatch` says): recording
/// and submitting (`step`), then waiting for the poses (`wait_snapshot`, which includes the GPU
/// time), medians over 30 steps after 30 settling ones. The host CPU column is the time the
/// calling thread spent on a CPU inside `step` (Linux: `/proc/thread-self/schedstat`), which
/// leaves out time blocked in the driver: on lavapipe, whose queue submit runs the kernels
/// before it returns unless `MESA_VK_ENABLE_SUBMIT_THREAD=1` moves them to a thread of their
/// own, the wall time of `step` is mostly the kernels', and this column is the recording's.
fn host_times(
    ctx: &GpuContext,
    heights: &[u32],
    color_dispatch: ColorDispatch,
    substep_dispatch: SubstepDispatch,
) -> Result<(), Box<dyn std::error::Error>> {
    println!("\ncolor dispatch {color_dispatch:?}, substeps {substep_dispatch:?}:");
    println!(
        "\n| height | path | record and submit ms | host CPU in step ms | wait for poses ms | step ms | step p90 ms |"
    );
    println!("|---|---|---|---|---|---|---|");
    for &h in heights {
        let scene = tumble_scenes::pyramid(h as usize);
        let mut world = gpu_world_of(
            ctx,
            &scene,
            GpuWorldConfig {
                solver: SolverConfig {
                    substeps: SUBSTEPS,
                    ..Default::default()
                },
                color_dispatch,
                substep_dispatch,
                ..Default::default()
            },
        )?;
        let poses = ReadRequest {
            poses: true,
            ..Default::default()
        };
        let mut record = Vec::new();
        let mut cpu = Vec::new();
        let mut wait = Vec::new();
        let mut steps = Vec::new();
        for k in 0..60 {
            let cpu_start = thread_cpu_seconds();
            let start = std::time::Instant::now();
            world.request_reads(poses);
            world.step()?;
            let submitted = start.elapsed().as_secs_f64();
            if let (Some(a), Some(b)) = (cpu_start, thread_cpu_seconds())
                && k >= 30
            {
                cpu.push(b - a);
            }
            world.wait_snapshot()?;
            let done = start.elapsed().as_secs_f64();
            if k >= 30 {
                record.push(submitted);
                wait.push(done - submitted);
                steps.push(done);
            }
        }
        let median = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2] * 1e3
        };
        let (r, w) = (median(&mut record), median(&mut wait));
        let c = if cpu.is_empty() {
            "-".to_string()
        } else {
            format!("{:.3}", median(&mut cpu))
        };
        steps.sort_by(f64::total_cmp);
        println!(
            "| {h} | {:?} | {r:.3} | {c} | {w:.3} | {:.3} | {:.3} |",
            world.last_path().unwrap_or(SolvePath::Wide),
            r + w,
            steps[steps.len() * 9 / 10] * 1e3,
        );
    }
    Ok(())
}

/// Seconds the calling thread has spent on a CPU (the first field of Linux's
/// `/proc/thread-self/schedstat`, in nanoseconds); `None` where that file is missing.
fn thread_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: u64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns as f64 * 1e-9)
}
