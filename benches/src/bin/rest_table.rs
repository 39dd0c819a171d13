//! How long an uneven pile takes to come to rest and fall asleep on the CPU step, by solver
//! setting, and what each setting costs per step: the table of docs/solver.md ("Piles that
//! keep rocking").
//!
//! ```sh
//! cargo run --release -p tumble-benches --bin rest_table [-- --side 6 --layers 3 --seconds 30]
//! ```
//!
//! `--help` lists the flags and their defaults; an unknown flag or value is an error.
//!
//! The pile (`tumble_tests::facade::add_uneven_pile`): `side` x `side` columns of `layers`
//! cubes of 0.5 m on a floor, each cube raised 3 cm per layer, shifted sideways by up to 8 mm
//! and tilted by up to 0.02 rad about each axis (seeded), so the cubes fall, land unevenly and
//! settle. Each row steps it with sleep on
//! until every cube sleeps or `seconds` of simulated time pass, and reports when it fell
//! asleep, the fastest cube at the end, and the median wall time of a step over the run. No
//! value is asserted; this is a measurement.

use std::time::{Duration, Instant};

use clap::Parser;
use tumble::prelude::*;
use tumble::{EffectOverrides, EffectSwitch, FrictionPasses};
use tumble_benches::cli::count;
use tumble_tests::facade::{add_uneven_pile, floor_desc};

/// How long an uneven pile takes to rest and fall asleep, by solver setting.
#[derive(Parser, Debug)]
struct Args {
    /// Columns of the pile along x and along z.
    #[arg(long, default_value_t = 6, value_parser = count())]
    side: usize,
    /// Cubes in each column.
    #[arg(long, default_value_t = 3, value_parser = count())]
    layers: usize,
    /// Most simulated seconds to wait for the pile to sleep.
    #[arg(long, default_value_t = 30, value_parser = count())]
    seconds: usize,
}

/// The uneven pile in a world with `solver` and sleep on; the cubes' handles.
fn pile(side: usize, layers: usize, solver: SolverConfig) -> (World, Vec<BodyHandle>) {
    let config = WorldConfig {
        solver,
        effects: EffectOverrides {
            sleep: EffectSwitch::On,
            ..Default::default()
        },
        ..Default::default()
    };
    let mut world = World::new(config).expect("a valid config");
    world.add_body(floor_desc(20.0)).expect("a valid floor");
    let cubes = add_uneven_pile(&mut world, side, layers);
    (world, cubes)
}

fn main() {
    let Args {
        side,
        layers,
        seconds,
    } = Args::parse();
    let base = SolverConfig::default();
    let default_name = format!(
        "default ({} substeps at {} Hz, {} iteration, {} relax pass)",
        base.substeps, base.contact_hertz, base.iterations, base.relax_iterations
    );
    let rows: [(&str, SolverConfig); 7] = [
        (default_name.as_str(), base),
        (
            "Box2D v3's 4 substeps at 30 Hz",
            SolverConfig {
                substeps: 4,
                contact_hertz: 30.0,
                ..base
            },
        ),
        (
            "2 iterations",
            SolverConfig {
                iterations: 2,
                ..base
            },
        ),
        (
            "2 relax passes",
            SolverConfig {
                relax_iterations: 2,
                ..base
            },
        ),
        (
            "8 substeps",
            SolverConfig {
                substeps: 8,
                ..base
            },
        ),
        (
            "no warm starting",
            SolverConfig {
                warm_start: false,
                ..base
            },
        ),
        (
            "friction in the relax passes only",
            SolverConfig {
                friction_passes: FrictionPasses::RelaxOnly,
                ..base
            },
        ),
    ];
    println!(
        "{side} x {side} x {layers} pile ({} cubes), at most {seconds} s\n",
        side * side * layers
    );
    println!("| solver | asleep after, s | fastest cube at the end, m/s | step, ms (median) |");
    println!("|---|---:|---:|---:|");
    for (name, solver) in rows {
        let (mut world, cubes) = pile(side, layers, solver);
        let steps = seconds * 60;
        let mut times = Vec::with_capacity(steps);
        let mut asleep_at = None;
        for step in 1..=steps {
            let t = Instant::now();
            world.step().expect("a valid world steps");
            times.push(t.elapsed());
            if world.sleeping_count() == cubes.len() {
                asleep_at = Some(step);
                break;
            }
        }
        let fastest = cubes
            .iter()
            .map(|&h| world.linear_velocity(h).expect("a live body").norm())
            .fold(0.0, Real::max);
        times.sort();
        let median: Duration = times[times.len() / 2];
        let asleep = asleep_at.map_or("never".to_string(), |s| format!("{:.1}", s as f64 / 60.0));
        println!(
            "| {name} | {asleep} | {fastest:.3} | {:.3} |",
            median.as_secs_f64() * 1e3
        );
    }
}
