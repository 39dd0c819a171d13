//! Sinking, drift and end speed of the load-bearing scenes under solver settings given on the
//! command line, for tuning the soft contacts:
//!
//! `cargo run --release -p tumble-tests --example contact_sweep -- [scene,...] [key=value ...]`
//!
//! Keys: `kind` (soft | baumgarte: `SolverConfig::default()` or `SolverConfig::baumgarte()`,
//! so give it first), `substeps`, `iterations`, `relax`, `hertz`, `zeta`, `steps`. Scenes:
//! mass_ratio, wide_on_small, stack_20, pyramid_12, wall_10x10 (default: these five),
//! pool_512 and pyramid_24. Sink and drift are the largest over the run, end values those
//! after the last step; with `TRACE` set in the environment, the first 40 steps print every
//! dynamic body's height change, mm. docs/solver.md ("Contacts under load") has the
//! measurements.

use tumble::prelude::*;
use tumble::scenes::{self, Scene};

fn scene(name: &str) -> Scene {
    match name {
        "mass_ratio" => scenes::mass_ratio(),
        "wide_on_small" => scenes::wide_on_small(),
        "stack_20" => scenes::stack(20),
        "pyramid_12" => scenes::pyramid(12),
        "wall_10x10" => scenes::wall(10, 10),
        "pool_512" => scenes::pool(512),
        "pyramid_24" => scenes::pyramid(24),
        other => panic!("unknown scene {other}"),
    }
}

fn main() {
    let mut solver = SolverConfig::default();
    let mut steps = 600usize;
    let mut names = vec![
        "mass_ratio",
        "wide_on_small",
        "stack_20",
        "pyramid_12",
        "wall_10x10",
    ]
    .into_iter()
    .map(String::from)
    .collect::<Vec<_>>();
    for arg in std::env::args().skip(1) {
        let Some((key, value)) = arg.split_once('=') else {
            names = arg.split(',').map(String::from).collect();
            continue;
        };
        let num = || value.parse::<f32>().expect("number");
        match key {
            "kind" if value == "baumgarte" => solver = SolverConfig::baumgarte(),
            "kind" => solver = SolverConfig::default(),
            "substeps" => solver.substeps = num() as u32,
            "iterations" => solver.iterations = num() as u32,
            "relax" => solver.relax_iterations = num() as u32,
            "hertz" => solver.contact_hertz = num(),
            "zeta" => solver.damping_ratio = num(),
            "steps" => steps = num() as usize,
            other => panic!("unknown key {other}"),
        }
    }
    println!("{solver:?}");
    println!(
        "scene          sink_mm  end_sink_mm  drift_mm  end_speed_mm/s  end_rms_mm/s  ms/step"
    );
    for name in &names {
        let scene = scene(name);
        let config = WorldConfig {
            solver,
            ..Default::default()
        };
        let (mut world, handles) = World::from_scene(&scene, config).expect("scene");
        let dynamic: Vec<BodyHandle> = handles
            .iter()
            .copied()
            .filter(|&h| world.kind(h).unwrap() == BodyKind::Dynamic)
            .collect();
        let start: Vec<Vec3> = dynamic
            .iter()
            .map(|&h| world.pose(h).unwrap().translation.vector)
            .collect();
        let (mut sink, mut drift) = (0.0f32, 0.0f32);
        let t0 = std::time::Instant::now();
        let trace = std::env::var("TRACE").is_ok();
        for step in 0..steps {
            world.step().expect("step");
            if trace && step < 40 {
                let ys: Vec<String> = dynamic
                    .iter()
                    .zip(&start)
                    .map(|(&h, s)| {
                        format!(
                            "{:8.2}",
                            (world.pose(h).unwrap().translation.vector - s).y * 1e3
                        )
                    })
                    .collect();
                println!("{step:3} {}", ys.join(" "));
            }
            for (&h, s) in dynamic.iter().zip(&start) {
                let d = world.pose(h).unwrap().translation.vector - s;
                sink = sink.max(-d.y);
                drift = drift.max((d.x * d.x + d.z * d.z).sqrt());
            }
        }
        let end_sink = dynamic
            .iter()
            .zip(&start)
            .map(|(&h, s)| s.y - world.pose(h).unwrap().translation.vector.y)
            .fold(0.0f32, f32::max);
        let ms = t0.elapsed().as_secs_f64() * 1e3 / steps as f64;
        let speeds: Vec<f32> = dynamic
            .iter()
            .map(|&h| {
                let v = world.linear_velocity(h).unwrap().norm();
                let w = world.angular_velocity(h).unwrap().norm();
                v + w * world.half_extents(h).unwrap().norm()
            })
            .collect();
        let speed = speeds.iter().copied().fold(0.0f32, f32::max);
        let rms = (speeds.iter().map(|s| s * s).sum::<f32>() / speeds.len() as f32).sqrt();
        println!(
            "{name:<14} {:>7.1} {:>12.1} {:>9.2} {:>15.2} {:>13.2} {:>8.3}",
            sink * 1e3,
            end_sink * 1e3,
            drift * 1e3,
            speed * 1e3,
            rms * 1e3,
            ms
        );
    }
}
