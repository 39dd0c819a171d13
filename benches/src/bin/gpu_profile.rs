//! Where a whole GPU step's time goes: per-pass GPU times (timestamp queries) of
//! `tumble_gpu::step::GpuWorld` on scenes, summed by pass name and averaged over steps,
//! with the counts that drive them (manifolds, colors used, overflow set).
//!
//! ```sh
//! cargo run --release -p tumble-benches --bin gpu_profile -- 24 50
//! cargo run --release -p tumble-benches --bin gpu_profile -- stack20 pyramid24
//! ```
//!
//! `--help` lists the flags and their defaults; an unknown flag or value is an error.
//!
//! Arguments are scenes: a bare number is a pyramid of that height, otherwise a scene name
//! (stackN, pyramidH, poolN; default 24 and 50). Each scene settles for 60 steps first so
//! warm starts and color seeds are in their steady state, then 20 steps are profiled.

use std::collections::BTreeMap;
use std::time::Instant;

use clap::Parser;
use tumble_benches::cli::SceneName;
use tumble_benches::gpu_pool::contact_counts;
use tumble_gpu::GpuContext;
use tumble_gpu::solver::constants::COLOR_OFFSETS_LEN;
use tumble_gpu::step::GpuWorldConfig;
use tumble_tests::scene_support::gpu_world_of;

/// Steps before profiling: one second at 60 Hz.
const SETTLE_STEPS: usize = 60;
/// Steps profiled.
const PROFILED_STEPS: usize = 20;

/// Per-pass GPU times of the whole GPU step on scenes.
#[derive(Parser, Debug)]
struct Args {
    /// Scenes, one profile each: a pyramid height (24), or a name (stack20, pyramid24, pool1000).
    #[arg(default_values = ["24", "50"], value_parser = profile_scene)]
    scenes: Vec<SceneName>,
}

/// A bare height of at least 1 is a pyramid; anything else parses as a scene name.
fn profile_scene(text: &str) -> Result<SceneName, String> {
    match text.parse::<usize>() {
        Ok(h) if h >= 1 => Ok(SceneName::Pyramid(h)),
        _ => text.parse(),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let Args { scenes } = Args::parse();
    let ctx = GpuContext::new()?;
    println!("device: {} ({:?})", ctx.info.name, ctx.info.backend);
    for name in scenes {
        let scene = name.build();
        let mut world = gpu_world_of(
            &ctx,
            &scene,
            GpuWorldConfig {
                timestamps: true,
                ..Default::default()
            },
        )?;
        for _ in 0..SETTLE_STEPS {
            world.step()?;
        }
        ctx.wait_idle()?;
        let mut sums: BTreeMap<&'static str, (f64, usize)> = BTreeMap::new();
        let clock = Instant::now();
        for _ in 0..PROFILED_STEPS {
            world.step()?;
            for (name, seconds) in world.timings()? {
                let e = sums.entry(name).or_default();
                e.0 += seconds;
                e.1 += 1;
            }
        }
        let wall = clock.elapsed().as_secs_f64() / PROFILED_STEPS as f64;
        let (manifolds, points) = contact_counts(&mut world)?;
        let offsets: Vec<u32> = ctx.read_buffer(
            world.solver().color_offsets(),
            0,
            u64::from(COLOR_OFFSETS_LEN),
        )?;
        let sizes: Vec<u32> = offsets.windows(2).map(|w| w[1] - w[0]).collect();
        let used = sizes[..sizes.len() - 1].iter().filter(|&&s| s > 0).count();
        println!(
            "\n{name}: {} bodies, {manifolds} manifolds with points, {points} points, \
             path {:?}, colors used {used}, overflow set {}",
            scene.bodies.len(),
            world.last_path(),
            sizes[sizes.len() - 1]
        );
        println!("color sizes: {sizes:?}");
        let total: f64 = sums.values().map(|v| v.0).sum::<f64>() / PROFILED_STEPS as f64;
        println!(
            "GPU time per step {:.3} ms (timestamps), wall per step with timings read {:.3} ms",
            total * 1e3,
            wall * 1e3
        );
        let mut rows: Vec<_> = sums.into_iter().collect();
        rows.sort_by(|a, b| b.1.0.total_cmp(&a.1.0));
        println!("| pass | ms/step | passes/step | share |");
        println!("|---|---|---|---|");
        for (name, (seconds, count)) in rows {
            let per_step = seconds / PROFILED_STEPS as f64;
            println!(
                "| {name} | {:.3} | {} | {:.1}% |",
                per_step * 1e3,
                count / PROFILED_STEPS,
                100.0 * per_step / total
            );
        }
    }
    Ok(())
}
