//! Step time of each effect forced on and skipped, on a pool that does not need it, and the
//! awake and asleep step of a settled pool: the table of docs/benchmarks.md ("Effects").
//!
//! ```sh
//! cargo run --release -p tumble-benches --bin effects_table [-- --cubes 1000 --steps 40 --gpu]
//! ```
//!
//! `--gpu` runs the effect rows on `Backend::Gpu` (sleep rows are CPU only: the GPU backends
//! do not sleep).
//!
//! Both worlds of a row step the same scene in lockstep (one step of each in turn, so load on
//! the machine hits both alike); the table gives the median step time of each. The program
//! also checks that the two worlds end bit for bit equal, which is the point of a skip.

use std::time::{Duration, Instant};

use tumble::prelude::*;
use tumble::{EffectOverrides, EffectSwitch, Effects};
use tumble_benches::effect_pool::{PoolOptions, effect_pool, with_sleep};

/// Steps before timing: the cubes fall and pile up (1.5 s at 60 Hz), so the timed steps have
/// the contacts of a pile.
const WARMUP_STEPS: usize = 90;
/// Most steps to wait for the pool to sleep (30 s at 60 Hz).
const MAX_SETTLE_STEPS: usize = 1800;

fn arg(name: &str, default: usize) -> usize {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn median(mut t: Vec<Duration>) -> Duration {
    t.sort();
    t[t.len() / 2]
}

fn bits(world: &World) -> Vec<u32> {
    world
        .handles()
        .iter()
        .flat_map(|&h| {
            let p = world.pose(h).unwrap();
            let v = world.linear_velocity(h).unwrap();
            let mut out: Vec<u32> = p.translation.vector.iter().map(|x| x.to_bits()).collect();
            out.extend(p.rotation.coords.iter().map(|x| x.to_bits()));
            out.extend(v.iter().map(|x| x.to_bits()));
            out
        })
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

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn main() {
    let cubes = arg("--cubes", 1000);
    let steps = arg("--steps", 40);
    type Set = fn(&mut EffectOverrides, EffectSwitch);
    type Get = fn(&Effects) -> bool;
    let gpu = std::env::args().any(|a| a == "--gpu");
    let pool = PoolOptions {
        cubes,
        backend: if gpu { Backend::Gpu } else { Backend::Cpu },
        ..Default::default()
    };
    let rows: [(&str, &str, PoolOptions, EffectOverrides, Set, Get); 6] = [
        (
            "friction",
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
            "restitution",
            "pool (no bounce)",
            pool,
            EffectOverrides::default(),
            |e, s| e.restitution = s,
            |e| e.restitution,
        ),
        (
            "gravity",
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
            "rotation",
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
            "kinematic",
            "pool, sleep on",
            pool,
            with_sleep(),
            |e, s| e.kinematic = s,
            |e| e.kinematic,
        ),
        (
            "sleep",
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
    for (name, scene, options, base, set, get) in rows {
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

    if gpu {
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
