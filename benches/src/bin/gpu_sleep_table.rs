//! The awake and asleep step of a settled pool on the GPU world: the GPU row of
//! docs/benchmarks.md's sleep measurement (`effects_table` gives the CPU one).
//!
//! ```sh
//! cargo run --release -p tumble-benches --bin gpu_sleep_table [-- --cubes 1000 --steps 40 --stages]
//! ```
//!
//! `--help` lists the flags and their defaults; an unknown flag or value is an error.
//!
//! `--stages` adds the GPU time of each stage in the last timed step of each world, from
//! timestamp queries (where the device has them).
//!
//! Three GPU worlds drop the same pool of cubes: one with sleep off, two with sleep on, of
//! which one skips idle steps (the default: a step that would repeat an idle one records
//! only its stats copy, see `tumble_gpu::step::idle`) and one records every stage of every
//! step (what the sleeping bodies still cost in the stages themselves). They step in
//! lockstep until every cube of the sleeping worlds sleeps (the first has then settled the
//! same way); then each step of each is timed to completion (submit and wait for the
//! device), and the table gives the median step times and their ratios to the awake step.
//! No timing is asserted: the numbers mean something on a real GPU only, not on a software
//! rasterizer.

use std::time::{Duration, Instant};

use clap::Parser;
use tumble_benches::cli::{PoolSize, median, ms};
use tumble_benches::gpu_pool::{PoolRun, gpu_pool};
use tumble_gpu::GpuContext;
use tumble_gpu::step::{GpuWorld, ReadRequest};

/// The awake and asleep step of a settled pool on the GPU world.
#[derive(Parser, Debug)]
struct Args {
    #[command(flatten)]
    size: PoolSize,
    /// Adds the GPU time of each stage in the last timed step of each world.
    #[arg(long)]
    stages: bool,
}

/// Most steps to wait for the pool to sleep (30 s at 60 Hz), as the CPU measurement does.
const MAX_SETTLE_STEPS: usize = 1800;
/// Steps between checks of the sleeping count while settling (each check waits for the GPU).
const CHECK_EVERY: usize = 10;
/// Walls of the pool before its cubes.
const WALLS: usize = 5;

/// Only the sleeping flags.
const SLEEPING: ReadRequest = ReadRequest {
    poses: false,
    velocities: false,
    contacts: false,
    sleeping: true,
    summary: false,
};

/// One step, waited for.
fn timed_step(world: &mut GpuWorld) -> Duration {
    let t = Instant::now();
    world.step().expect("a valid world steps");
    world.context().wait_idle().expect("the device answers");
    t.elapsed()
}

fn main() {
    let Args {
        size: PoolSize { cubes, steps },
        stages,
    } = Args::parse();
    let ctx = GpuContext::new().expect("a GPU adapter");
    let run = |sleep, skip_idle| PoolRun {
        sleep,
        skip_idle,
        timestamps: stages,
    };
    let mut asleep = gpu_pool(&ctx, cubes, run(true, true));
    let mut recorded = gpu_pool(&ctx, cubes, run(true, false));
    let mut awake = gpu_pool(&ctx, cubes, run(false, true));
    let mut settle = 0;
    let mut sleeping = 0;
    while sleeping < cubes && settle < MAX_SETTLE_STEPS {
        for _ in 0..CHECK_EVERY {
            asleep.step().expect("a valid world steps");
            recorded.step().expect("a valid world steps");
            awake.step().expect("a valid world steps");
        }
        settle += CHECK_EVERY;
        let snap = asleep.read_now(SLEEPING).expect("the device answers");
        sleeping = snap.sleeping[WALLS..].iter().filter(|&&s| s).count();
    }
    let (mut t_awake, mut t_asleep, mut t_recorded) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..steps {
        t_awake.push(timed_step(&mut awake));
        t_asleep.push(timed_step(&mut asleep));
        t_recorded.push(timed_step(&mut recorded));
    }
    let (t_awake, t_asleep, t_recorded) = (median(t_awake), median(t_asleep), median(t_recorded));
    let ratio = |t: Duration| t.as_secs_f64() / t_awake.as_secs_f64();
    println!(
        "{cubes} cubes on {}, median of {steps} steps",
        ctx.info.name
    );
    println!(
        "settled pool after {settle} steps ({:.1} s), {sleeping} of {cubes} asleep\n",
        settle as f64 / 60.0
    );
    println!("| GPU pool step | ms |\n|---|---:|");
    println!("| awake (sleep off) | {:.3} |", ms(t_awake));
    println!("| asleep | {:.3} |", ms(t_asleep));
    println!("| asleep, every stage recorded | {:.3} |", ms(t_recorded));
    println!("| asleep / awake | {:.3} |", ratio(t_asleep));
    println!(
        "| asleep, every stage recorded / awake | {:.3} |",
        ratio(t_recorded)
    );
    println!(
        "\nidle steps skipped: {} of {} (every stage recorded: {})",
        asleep.idle_steps(),
        asleep.steps(),
        recorded.idle_steps()
    );
    if stages {
        let awake_stages = awake.timings().expect("the device answers");
        let asleep_stages = recorded.timings().expect("the device answers");
        println!("\n| stage | awake, ms | asleep (every stage recorded), ms |\n|---|---:|---:|");
        for (name, t) in &asleep_stages {
            let a = awake_stages
                .iter()
                .find(|(n, _)| n == name)
                .map_or("-".to_string(), |(_, t)| format!("{:.3}", t * 1e3));
            println!("| {name} | {a} | {:.3} |", t * 1e3);
        }
    }
}
