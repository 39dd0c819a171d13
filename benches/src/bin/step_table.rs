//! Milliseconds per step for Tumble's backends and rapier3d, measured side by side in one run.
//!
//! ```sh
//! cargo run --release -p tumble-benches --features rapier-parallel --bin step_table -- \
//!     --scenes stack20,pyramid24,pyramid50 --steps 60
//! ```
//!
//! Every engine runs the same `tumble-scenes` scene at the same time step and substep count.
//! Each row reports the median and the 90th percentile of the wall time of `step()` after a
//! warm-up, and the largest horizontal drift of any dynamic body at the end, so that a faster
//! row can be checked for holding its stack just as well. GPU rows include the GPU work: a
//! step's poses are read back before the clock stops.

use std::time::Instant;

use tumble::prelude::*;
use tumble_scenes::{RapierOptions, Scene, build_rapier_with, builders};

/// Steps run before timing starts: pipelines compile, buffers grow, caches warm up.
const WARMUP_STEPS: usize = 10;

struct Args {
    scenes: Vec<String>,
    backends: Vec<String>,
    steps: usize,
    substeps: u32,
}

fn parse_args() -> Args {
    let mut args = Args {
        scenes: vec!["stack20".into(), "pyramid24".into(), "pyramid50".into()],
        backends: vec!["gpu".into(), "hybrid".into(), "cpu".into(), "rapier".into()],
        steps: 60,
        substeps: 4,
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let value = it.next().unwrap_or_default();
        let list = || value.split(',').map(str::to_owned).collect::<Vec<_>>();
        match flag.as_str() {
            "--scenes" => args.scenes = list(),
            "--backends" => args.backends = list(),
            "--steps" => args.steps = value.parse().expect("--steps takes a count"),
            "--substeps" => args.substeps = value.parse().expect("--substeps takes a count"),
            other => panic!("unknown flag {other}: see the module docs"),
        }
    }
    args
}

fn scene_named(name: &str) -> Scene {
    if let Some(n) = name.strip_prefix("stack") {
        return builders::stack(n.parse().expect("stackN"));
    }
    if let Some(h) = name.strip_prefix("pyramid") {
        return builders::pyramid(h.parse().expect("pyramidH"));
    }
    if let Some(n) = name.strip_prefix("pool") {
        return builders::pool(n.parse().expect("poolN"));
    }
    panic!("unknown scene {name}: stackN, pyramidH or poolN")
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

fn run_tumble(scene: &Scene, backend: Backend, substeps: u32, steps: usize) -> Result<Run, Error> {
    let solver = SolverConfig {
        substeps,
        ..SolverConfig::default()
    };
    let config = WorldConfig {
        backend,
        solver,
        ..WorldConfig::default()
    };
    let (mut world, handles) = World::from_scene(scene, config)?;
    let mut ms = Vec::with_capacity(steps);
    for i in 0..WARMUP_STEPS + steps {
        let t0 = Instant::now();
        world.step()?;
        // Reading one pose forces the step's results back to the host on GPU backends.
        world.pose(handles[handles.len() - 1])?;
        if i >= WARMUP_STEPS {
            ms.push(t0.elapsed().as_secs_f64() * 1e3);
        }
    }
    let poses = handles
        .iter()
        .map(|&h| {
            let p = world.pose(h)?.translation.vector;
            Ok(([p.x, p.y, p.z], world.kind(h)? == BodyKind::Dynamic))
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let stats = world.stats();
    let t = &stats.timings;
    let to_ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
    let note = format!(
        "{} pairs, {} contacts, {} colors; last step ms: aabb {:.2} broad {:.2} narrow {:.2} color {:.2} solve {:.2} finish {:.2}",
        stats.pairs,
        stats.contact_points,
        stats.colors,
        to_ms(t.update_aabbs),
        to_ms(t.broad_phase),
        to_ms(t.narrow_phase),
        to_ms(t.color),
        to_ms(t.solve),
        to_ms(t.finish)
    );
    Ok(Run {
        ms,
        drift: horizontal_drift(scene, &poses),
        note,
    })
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
            "parallel, {} threads",
            std::thread::available_parallelism().map_or(1, |n| n.get())
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
    let args = parse_args();
    println!(
        "| scene | bodies | engine | median ms/step | p90 ms/step | max drift (mm) | vs rapier | notes |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for name in &args.scenes {
        let scene = scene_named(name);
        let mut rows = Vec::new();
        for backend in &args.backends {
            let run = match backend.as_str() {
                "cpu" => run_tumble(&scene, Backend::Cpu, args.substeps, args.steps),
                "gpu" => run_tumble(&scene, Backend::Gpu, args.substeps, args.steps),
                "hybrid" => run_tumble(&scene, Backend::Hybrid, args.substeps, args.steps),
                "rapier" => Ok(run_rapier(&scene, args.substeps, args.steps)),
                other => panic!("unknown backend {other}: cpu, gpu, hybrid or rapier"),
            };
            rows.push((backend.clone(), run));
        }
        let median_of = |run: &Run| {
            let mut ms = run.ms.clone();
            ms.sort_by(f64::total_cmp);
            (percentile(&ms, 0.5), percentile(&ms, 0.9))
        };
        let rapier_median = rows
            .iter()
            .find(|(b, _)| b == "rapier")
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
