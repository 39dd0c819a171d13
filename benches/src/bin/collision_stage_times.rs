//! Per-stage GPU time of the collision stages (timestamp queries around each stage's compute
//! pass), the wall time of a step with its readback (every candidate pair's manifold, and
//! only the manifolds in contact, compacted), and the CPU stages on the same scene.
//!
//! ```text
//! cargo run --release -p tumble-benches --bin collision_stage_times -- [--csv] [bodies...]
//! ```
//! Default body counts: 1000 10000 100000; `--help` lists the flags. Set `TUMBLE_ADAPTER` to pick an adapter. With
//! `--csv` the rows are printed as CSV (the committed results in `benches/results/`).

use std::time::Instant;

use clap::Parser;
use tumble_benches::cli::count;

use tumble_benches::random_pile;
use tumble_geometry::Aabb;
use tumble_gpu::collision;
use tumble_gpu::{CollisionConfig, GpuCollision, GpuContext, ReadbackRequest, StageTimer};

/// Steps timed per scene (after the warm-up), enough for a stable median.
const TIMED_STEPS: usize = 20;
/// Steps run before timing: pipelines are compiled lazily by some drivers on first use.
const WARM_UP_STEPS: usize = 3;

/// The passes `GpuCollision::record` opens, in order.
const STAGES: [&str; 5] = [
    collision::UPDATE_AABBS,
    collision::BROAD_PHASE_SORT_BODIES,
    collision::BROAD_PHASE_SWEEP,
    collision::BROAD_PHASE_SORT_PAIRS,
    collision::NARROW_PHASE,
];

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Per-stage GPU times of the collision stages on random piles.
#[derive(Parser, Debug)]
struct Args {
    /// Print the rows as CSV (the committed results in `benches/results/`).
    #[arg(long)]
    csv: bool,
    /// Body counts, one random pile each.
    #[arg(default_values_t = [1000, 10_000, 100_000], value_parser = count())]
    counts: Vec<usize>,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let Args { csv, counts } = Args::parse();
    let ctx = GpuContext::new()?;
    // Quoted: adapter names contain commas.
    let adapter = format!("\"{} ({:?})\"", ctx.info.name, ctx.info.backend);
    if csv {
        println!(
            "adapter,bodies,pairs,touching,update_aabbs_ms,sort_bodies_ms,sweep_ms,sort_pairs_ms,narrow_phase_ms,gpu_total_ms,step_and_readback_ms,readback_host_ms,step_and_touching_readback_ms,cpu_broad_phase_ms,cpu_narrow_phase_ms"
        );
    } else {
        println!("adapter: {adapter}; timestamps: {}", ctx.has_timestamps);
    }
    if !csv {
        println!(
            "{:>8} {:>8} {:>8} | {:>8} {:>8} {:>8} {:>8} {:>9} {:>8} | {:>10} {:>8} {:>10} | {:>9} {:>9}",
            "bodies",
            "pairs",
            "touching",
            "aabbs ms",
            "sort ms",
            "sweep ms",
            "pairs ms",
            "narrow ms",
            "gpu ms",
            "step+rb ms",
            "rb ms",
            "step+t ms",
            "cpu bp ms",
            "cpu np ms"
        );
    }
    for n in counts {
        let (poses, velocities, shapes) = random_pile::random_pile(n, 42);
        // Every manifold afresh, as the CPU column computes them: the same poses stepped again
        // would otherwise recycle every manifold after the first step.
        let config = CollisionConfig {
            recycle_distance: 0.0,
            ..CollisionConfig::default()
        };
        let mut gpu = GpuCollision::new(&ctx, config)?;
        gpu.set_bodies(&poses, &velocities, &shapes)?;
        for _ in 0..WARM_UP_STEPS {
            gpu.step_and_read(ReadbackRequest::CONTACTS)?;
        }
        let mut timer = StageTimer::new(&ctx);
        let mut stages: Vec<Vec<f64>> = vec![Vec::new(); STAGES.len()];
        let mut walls = Vec::new();
        let mut host_reads = Vec::new();
        let mut snap = None;
        for _ in 0..TIMED_STEPS {
            let start = Instant::now();
            let mut encoder = ctx.device.create_command_encoder(&Default::default());
            gpu.record(&mut encoder, &mut timer)?;
            timer.resolve(&mut encoder);
            let plan = gpu.record_readback(&mut encoder, ReadbackRequest::CONTACTS)?;
            ctx.queue.submit([encoder.finish()]);
            let pending = gpu.submit_readback(plan);
            // Split the wall time: until the GPU is done, then mapping and decoding.
            ctx.wait_idle()?;
            let done = Instant::now();
            snap = Some(gpu.receive(pending)?);
            walls.push(start.elapsed().as_secs_f64() * 1e3);
            host_reads.push(done.elapsed().as_secs_f64() * 1e3);
            for (name, seconds) in timer.read()? {
                if let Some(i) = STAGES.iter().position(|s| *s == name) {
                    stages[i].push(seconds * 1e3);
                }
            }
        }
        let snap = snap.expect("timed at least one step");
        // The same steps reading back only the manifolds in contact, compacted on the GPU.
        let mut touching_walls = Vec::new();
        for _ in 0..TIMED_STEPS {
            let start = Instant::now();
            gpu.step_and_read(ReadbackRequest::TOUCHING)?;
            touching_walls.push(start.elapsed().as_secs_f64() * 1e3);
        }
        let touching = snap.manifolds.iter().filter(|m| m.len > 0).count();
        let stage_ms: Vec<f64> = stages
            .into_iter()
            .map(|s| if s.is_empty() { f64::NAN } else { median(s) })
            .collect();

        // The CPU stages on the same AABBs and pairs, single-threaded.
        let aabbs: Vec<Aabb> = gpu
            .read_aabbs()?
            .iter()
            .map(tumble_gpu::kernels::aabb_from_gpu)
            .collect();
        let statics: Vec<bool> = shapes.iter().map(|s| s.is_static()).collect();
        let start = Instant::now();
        let pairs = tumble_broad::sweep_and_prune_filtered(&aabbs, &statics)?;
        let cpu_broad = start.elapsed().as_secs_f64() * 1e3;
        let start = Instant::now();
        let found = pairs
            .iter()
            .filter(|&&p| {
                tumble_gpu::kernels::collide_gpu_pair(
                    &poses,
                    &velocities,
                    &shapes,
                    p,
                    None,
                    config.margin,
                    config.dt,
                )
                .is_some()
            })
            .count();
        let cpu_narrow = start.elapsed().as_secs_f64() * 1e3;
        assert_eq!(pairs, snap.pairs, "GPU and CPU pair lists differ");
        assert!(
            found.abs_diff(touching) * 100 <= touching.max(1),
            "contact counts differ"
        );
        let gpu_ms = stage_ms.iter().sum::<f64>();
        if csv {
            let stages: Vec<String> = stage_ms.iter().map(|t| format!("{t:.4}")).collect();
            println!(
                "{adapter},{n},{},{touching},{},{gpu_ms:.4},{:.4},{:.4},{:.4},{cpu_broad:.4},{cpu_narrow:.4}",
                snap.pairs.len(),
                stages.join(","),
                median(walls),
                median(host_reads),
                median(touching_walls)
            );
            continue;
        }
        println!(
            "{:>8} {:>8} {:>8} | {:>8.3} {:>8.3} {:>8.3} {:>8.3} {:>9.3} {:>8.3} | {:>10.3} {:>8.3} {:>10.3} | {:>9.3} {:>9.3}",
            n,
            snap.pairs.len(),
            touching,
            stage_ms[0],
            stage_ms[1],
            stage_ms[2],
            stage_ms[3],
            stage_ms[4],
            gpu_ms,
            median(walls),
            median(host_reads),
            median(touching_walls),
            cpu_broad,
            cpu_narrow
        );
    }
    Ok(())
}
