//! Step time of each effect forced on and skipped, on a pool that does not need it, and the
//! awake and asleep step of a settled pool: the table of docs/benchmarks.md ("Effects").
//!
//! ```sh
//! cargo run --release -p tumble-benches --bin effects_table [-- --cubes 1000 --steps 40 --gpu]
//! ```
//!
//! `--help` lists the flags and their defaults; an unknown flag or value is an error.
//!
//! `--gpu` runs the effect rows on `Backend::Gpu` (the asleep and awake rows are CPU only:
//! `gpu_sleep_table` gives the GPU's). `--diff NAME` runs only row NAME, untimed, and reports
//! the first step after which its two worlds differ in any bit, and how.
//!
//! Both worlds of a row step the same scene in lockstep (one step of each in turn, so load on
//! the machine hits both alike); the table gives the median step time of each. The program
//! also checks that the two worlds end bit for bit equal, which is the point of a skip.

use std::time::{Duration, Instant};

use clap::{Parser, ValueEnum};
use tumble::prelude::*;
use tumble::{EffectOverrides, EffectSwitch, Effects};
use tumble_benches::cli::{PoolSize, median, ms};
use tumble_benches::effect_pool::{PoolOptions, effect_pool, with_sleep};
use tumble_tests::bad_input::body_state;

/// Step time of each effect forced on and skipped, and of a settled pool awake and asleep.
#[derive(Parser, Debug)]
struct Args {
    #[command(flatten)]
    size: PoolSize,
    /// Runs the effect rows on `Backend::Gpu` (the asleep and awake rows are CPU only).
    #[arg(long)]
    gpu: bool,
    /// Runs only this row, untimed, and reports the first step after which its two worlds
    /// differ in any bit.
    #[arg(long, value_enum, value_name = "NAME")]
    diff: Option<Row>,
}

/// A row of the table: the effect it forces on and skips.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Row {
    /// Friction, on a frictionless pool.
    Friction,
    /// Restitution, on a pool that does not bounce.
    Restitution,
    /// Gravity, on a pool in zero gravity.
    Gravity,
    /// Rotation, on a pool whose rotations are locked.
    Rotation,
    /// Kinematic bodies, on a pool with none.
    Kinematic,
    /// Sleep, on a pool while it falls.
    Sleep,
}

impl Row {
    /// The row's name in the table, as `--diff` takes it.
    fn name(self) -> &'static str {
        match self {
            Row::Friction => "friction",
            Row::Restitution => "restitution",
            Row::Gravity => "gravity",
            Row::Rotation => "rotation",
            Row::Kinematic => "kinematic",
            Row::Sleep => "sleep",
        }
    }
}

/// Steps before timing: the cubes fall and pile up (1.5 s at 60 Hz), so the timed steps have
/// the contacts of a pile.
const WARMUP_STEPS: usize = 90;
/// Most steps to wait for the pool to sleep (30 s at 60 Hz).
const MAX_SETTLE_STEPS: usize = 1800;

/// Each body's pose (translation, rotation), linear and angular velocity, by component.
fn state(world: &World) -> Vec<[Real; 13]> {
    world
        .handles()
        .iter()
        .map(|&h| body_state(world, h))
        .collect()
}

/// `--diff NAME`: steps the row's two worlds in lockstep and reports the first step after
/// which any bit of any body's state differs, and how.
fn diff(name: &str, on: &mut World, off: &mut World, steps: usize) {
    const PARTS: [&str; 13] = [
        "x", "y", "z", "qi", "qj", "qk", "qw", "vx", "vy", "vz", "wx", "wy", "wz",
    ];
    for step in 1..=steps {
        on.step().unwrap();
        off.step().unwrap();
        let (a, b) = (state(on), state(off));
        let differing: Vec<usize> = (0..a.len())
            .filter(|&i| {
                a[i].iter()
                    .zip(&b[i])
                    .any(|(x, y)| x.to_bits() != y.to_bits())
            })
            .collect();
        if let Some(&first) = differing.first() {
            println!(
                "{name}: first difference after step {step}, in {} of {} bodies; body {first}:",
                differing.len(),
                a.len()
            );
            for (k, part) in PARTS.iter().enumerate() {
                let (x, y) = (a[first][k], b[first][k]);
                if x.to_bits() != y.to_bits() {
                    println!(
                        "  {part}: on {x:e} ({:#010x}), off {y:e} ({:#010x})",
                        x.to_bits(),
                        y.to_bits()
                    );
                }
            }
            return;
        }
    }
    println!("{name}: same bits for {steps} steps");
}

/// The bits of each body's pose and linear velocity (the first 10 components of its state).
fn bits(world: &World) -> Vec<u32> {
    state(world)
        .iter()
        .flat_map(|s| s[..10].iter().map(|x| x.to_bits()))
        .collect()
}

/// One step, and a pose read, which on `Backend::Gpu` waits for the step's results (a GPU
/// step returns before the GPU has run it).
fn step_and_read(world: &mut World) {
    world.step().unwrap();
    let last = *world.handles().last().expect("pools have bodies");
    world.pose(last).unwrap();
}

/// Median step times of two worlds stepped in lockstep.
fn race(a: &mut World, b: &mut World, steps: usize) -> (Duration, Duration) {
    let (mut ta, mut tb) = (Vec::new(), Vec::new());
    for _ in 0..steps {
        let t = Instant::now();
        step_and_read(a);
        ta.push(t.elapsed());
        let t = Instant::now();
        step_and_read(b);
        tb.push(t.elapsed());
    }
    (median(ta), median(tb))
}

fn main() {
    let Args {
        size: PoolSize { cubes, steps },
        gpu,
        diff: diff_row,
    } = Args::parse();
    type Set = fn(&mut EffectOverrides, EffectSwitch);
    type Get = fn(&Effects) -> bool;
    let pool = PoolOptions {
        cubes,
        backend: if gpu { Backend::Gpu } else { Backend::Cpu },
        ..Default::default()
    };
    let rows: [(Row, &str, PoolOptions, EffectOverrides, Set, Get); 6] = [
        (
            Row::Friction,
            "frictionless pool",
            PoolOptions {
                friction: 0.0,
                ..pool
            },
            EffectOverrides::default(),
            |e, s| e.friction = s,
            |e| e.friction,
        ),
        (
            Row::Restitution,
            "pool (no bounce)",
            pool,
            EffectOverrides::default(),
            |e, s| e.restitution = s,
            |e| e.restitution,
        ),
        (
            Row::Gravity,
            "pool in zero gravity",
            PoolOptions {
                gravity: 0.0,
                ..pool
            },
            EffectOverrides::default(),
            |e, s| e.gravity = s,
            |e| e.gravity,
        ),
        (
            Row::Rotation,
            "pool, rotations locked",
            PoolOptions {
                lock_rotations: true,
                ..pool
            },
            EffectOverrides::default(),
            |e, s| e.rotation = s,
            |e| e.rotation,
        ),
        (
            Row::Kinematic,
            "pool, sleep on",
            pool,
            with_sleep(),
            |e, s| e.kinematic = s,
            |e| e.kinematic,
        ),
        (
            Row::Sleep,
            "pool while falling",
            pool,
            EffectOverrides::default(),
            |e, s| e.sleep = s,
            |e| e.sleep,
        ),
    ];
    let side = if gpu { "GPU" } else { "CPU" };
    println!("{cubes} cubes, median of {steps} steps after {WARMUP_STEPS} warm-up steps, {side}\n");
    println!("| effect | scene | forced on, ms | skipped, ms | on / skipped | same bits |");
    println!("|---|---|---:|---:|---:|---|");
    for (row, scene, options, base, set, get) in rows {
        if diff_row.is_some_and(|d| d != row) {
            continue;
        }
        let name = row.name();
        let mut on_fx = base;
        set(&mut on_fx, EffectSwitch::On);
        let mut off_fx = base;
        set(&mut off_fx, EffectSwitch::Off);
        let mut on = effect_pool(options, on_fx);
        let mut off = effect_pool(options, off_fx);
        let mut auto = effect_pool(options, base);
        assert!(!get(&auto.effects()), "{name}: the scene needs the effect");
        assert!(get(&on.effects()) && !get(&off.effects()));
        auto.step().unwrap();
        if diff_row.is_some() {
            diff(name, &mut on, &mut off, WARMUP_STEPS + steps);
            continue;
        }
        for _ in 0..WARMUP_STEPS {
            on.step().unwrap();
            off.step().unwrap();
        }
        let (t_on, t_off) = race(&mut on, &mut off, steps);
        let same = if bits(&on) == bits(&off) { "yes" } else { "NO" };
        println!(
            "| {name} | {scene} | {:.3} | {:.3} | {:.2} | {same} |",
            ms(t_on),
            ms(t_off),
            t_on.as_secs_f64() / t_off.as_secs_f64()
        );
    }

    if gpu || diff_row.is_some() {
        return;
    }
    let mut asleep = effect_pool(pool, with_sleep());
    let mut awake = effect_pool(pool, EffectOverrides::default());
    let mut settle = 0;
    while asleep.sleeping_count() < cubes && settle < MAX_SETTLE_STEPS {
        asleep.step().unwrap();
        awake.step().unwrap();
        settle += 1;
    }
    let (t_awake, t_asleep) = race(&mut awake, &mut asleep, steps);
    println!(
        "\nsettled pool after {settle} steps ({:.1} s), {} of {cubes} asleep",
        settle as f64 / 60.0,
        asleep.sleeping_count()
    );
    println!("| pool step | ms |\n|---|---:|");
    println!("| awake (sleep off) | {:.3} |", ms(t_awake));
    println!("| asleep | {:.4} |", ms(t_asleep));
    println!(
        "| asleep / awake | {:.4} |",
        t_asleep.as_secs_f64() / t_awake.as_secs_f64()
    );
}
