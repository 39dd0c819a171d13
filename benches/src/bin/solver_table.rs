//! Drift and cost of each solver setting on the resting canonical scenes: the thesis's
//! Baumgarte comparison, reproduced with the soft step beside it and rapier3d as a reference.
//!
//! ```sh
//! cargo run --release -p tumble-benches --bin solver_table
//! cargo run --release -p tumble-benches --bin solver_table -- --scenes stack20 \
//!     --settings softstep4,rapier4 --steps 600
//! ```
//!
//! `--help` lists the flags and their defaults; an unknown flag or value is an error.
//!
//! Every row runs a fresh world for the scene's full length (10 s, 600 steps at 60 Hz) on the
//! CPU and reports the horizontal drift of the dynamic bodies (the largest x-z displacement of
//! any body from its start, at the end and at its worst during the run), whether the scene's
//! own drift criterion held at every step, and the median and mean wall time of one step.
//! Rapier rows use as many solver iterations as the Tumble row above them has substeps
//! (rapier's iterations are substeps of its soft-step solver). A second table splits each
//! Tumble row's mean step into its stages and gives the solve stage's cost per contact point
//! per pass (a pass is one visit of every constraint: the warm start, each biased iteration
//! and each relax iteration of every substep).

use std::time::Instant;

use clap::Parser;
use tumble::EffectOverrides;
use tumble::prelude::*;
use tumble_benches::cli::SceneName;
use tumble_scenes::{RapierOptions, Scene, SceneCheck, build_rapier_with};
use tumble_tests::scene_support::horizontal_drift;

/// One solver setting: its label in the table and how to run it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Setting {
    /// The thesis's projected Gauss-Seidel with `iterations` passes, one substep.
    Baumgarte { iterations: u32 },
    /// The soft step with `substeps` substeps (one biased and one relax pass each).
    SoftStep { substeps: u32 },
    /// Rapier3d with `iterations` solver iterations.
    Rapier { iterations: u32 },
}

impl Setting {
    fn label(self) -> String {
        match self {
            Setting::Baumgarte { iterations } => format!("tumble Baumgarte, {iterations} it"),
            Setting::SoftStep { substeps } => format!("tumble SoftStep, {substeps} sub"),
            Setting::Rapier { iterations } => format!("rapier3d, {iterations} it"),
        }
    }

    /// The name `--settings` selects it by: `baumgarte5`, `softstep4`, `rapier4`, ...
    fn key(self) -> String {
        match self {
            Setting::Baumgarte { iterations } => format!("baumgarte{iterations}"),
            Setting::SoftStep { substeps } => format!("softstep{substeps}"),
            Setting::Rapier { iterations } => format!("rapier{iterations}"),
        }
    }
}

/// The thesis's two Baumgarte settings (5: what a game would afford; 150: what the thesis ran
/// on the CPU), then the soft step at 1 to 8 substeps, each beside rapier at the same count.
const SETTINGS: [Setting; 10] = [
    Setting::Baumgarte { iterations: 5 },
    Setting::Baumgarte { iterations: 150 },
    Setting::SoftStep { substeps: 1 },
    Setting::Rapier { iterations: 1 },
    Setting::SoftStep { substeps: 2 },
    Setting::Rapier { iterations: 2 },
    Setting::SoftStep { substeps: 4 },
    Setting::Rapier { iterations: 4 },
    Setting::SoftStep { substeps: 8 },
    Setting::Rapier { iterations: 8 },
];

/// Drift and cost of each solver setting on the resting canonical scenes.
#[derive(Parser, Debug)]
struct Args {
    /// Scenes, comma-separated: stackN, pyramidH or poolN.
    #[arg(long, value_delimiter = ',', default_value = "stack20,pyramid12")]
    scenes: Vec<SceneName>,
    /// Steps per row [default: the scene's own length, 600 for the canonical scenes].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    steps: Option<u32>,
    /// Settings to run by key, comma-separated (baumgarte5, softstep4, rapier4, ...; an
    /// unknown key lists them all); all of them when left out.
    #[arg(long, value_delimiter = ',', value_parser = parse_setting)]
    settings: Vec<Setting>,
}

/// The setting `--settings` names by `key`; an unknown key is an error listing the keys.
fn parse_setting(key: &str) -> Result<Setting, String> {
    SETTINGS
        .into_iter()
        .find(|s| s.key() == key)
        .ok_or_else(|| {
            let keys: Vec<String> = SETTINGS.iter().map(|s| s.key()).collect();
            format!(
                "unknown setting {key:?}: expected one of {}",
                keys.join(", ")
            )
        })
}

/// What one row measured.
struct Row {
    /// Wall time of each step, ms.
    ms: Vec<f64>,
    /// Drift at the end of the run, m.
    final_drift: f32,
    /// Largest drift at any step, m.
    peak_drift: f32,
    /// Contact points solved in the last step.
    points: usize,
    /// Tumble's per-stage profile over the run (Tumble only).
    profile: Option<Profile>,
}

/// Where a Tumble run spent its time: per-stage means and the solver's cost per point.
struct Profile {
    /// Mean ms per step of each stage: AABBs, broad, narrow, color, solve, finish.
    stage_ms: [f64; 6],
    /// Mean contact points per step.
    points: f64,
    /// Passes over every constraint per step: per substep one warm start, the biased
    /// iterations and the relax iterations.
    passes: u32,
}

impl Profile {
    /// Solve-stage time per contact point per pass, ns (preparation and integration included,
    /// spread over the passes).
    fn solve_ns_per_point_pass(&self) -> f64 {
        self.stage_ms[4] * 1e6 / (self.points * f64::from(self.passes))
    }
}

/// A stepping engine: one step, then every body's centre.
trait Engine {
    fn step(&mut self);
    fn positions(&self) -> Vec<[f32; 3]>;
    /// Contact points the last step's solver saw.
    fn contact_points(&self) -> usize;
}

struct TumbleEngine {
    world: World,
    handles: Vec<BodyHandle>,
    /// Sum over the steps of each stage's ms.
    stage_ms: [f64; 6],
    /// Sum over the steps of the contact points solved.
    points: usize,
}

impl Engine for TumbleEngine {
    fn step(&mut self) {
        self.world.step().expect("a valid world steps");
        let stats = self.world.stats();
        let t = &stats.timings;
        let stages = [
            t.update_aabbs,
            t.broad_phase,
            t.narrow_phase,
            t.color,
            t.solve,
            t.finish,
        ];
        for (sum, d) in self.stage_ms.iter_mut().zip(stages) {
            *sum += d.as_secs_f64() * 1e3;
        }
        self.points += stats.contact_points;
    }
    fn positions(&self) -> Vec<[f32; 3]> {
        self.handles
            .iter()
            .map(|&h| {
                let t = self.world.pose(h).expect("live handle").translation.vector;
                [t.x, t.y, t.z]
            })
            .collect()
    }
    fn contact_points(&self) -> usize {
        self.world.stats().contact_points
    }
}

impl Engine for tumble_scenes::RapierWorld {
    fn step(&mut self) {
        tumble_scenes::RapierWorld::step(self);
    }
    fn positions(&self) -> Vec<[f32; 3]> {
        self.body_poses().into_iter().map(|(p, _)| p).collect()
    }
    fn contact_points(&self) -> usize {
        self.narrow_phase
            .contact_pairs()
            .flat_map(|pair| pair.solver_manifolds())
            .map(|m| m.data.solver_contacts.len())
            .sum()
    }
}

fn run(scene: &Scene, engine: &mut dyn Engine, steps: u32) -> Row {
    let mut ms = Vec::with_capacity(steps as usize);
    let mut peak_drift: f32 = 0.0;
    for _ in 0..steps {
        let t0 = Instant::now();
        engine.step();
        ms.push(t0.elapsed().as_secs_f64() * 1e3);
        peak_drift = peak_drift.max(horizontal_drift(scene, &engine.positions()));
    }
    Row {
        ms,
        final_drift: horizontal_drift(scene, &engine.positions()),
        peak_drift,
        points: engine.contact_points(),
        profile: None,
    }
}

fn run_setting(scene: &Scene, setting: Setting, steps: u32) -> Row {
    let solver = match setting {
        Setting::Baumgarte { iterations } => SolverConfig {
            iterations,
            ..SolverConfig::baumgarte()
        },
        Setting::SoftStep { substeps } => SolverConfig {
            substeps,
            ..SolverConfig::soft_step()
        },
        Setting::Rapier { iterations } => {
            let options = RapierOptions {
                solver_iterations: iterations as usize,
                ..RapierOptions::default()
            };
            return run(scene, &mut build_rapier_with(scene, &options), steps);
        }
    };
    let config = WorldConfig {
        solver,
        // The solver's own drift and cost: no body is put to sleep.
        effects: EffectOverrides::NO_SLEEP,
        ..WorldConfig::default()
    };
    let (world, handles) = World::from_scene(scene, config).expect("canonical scenes are valid");
    let mut engine = TumbleEngine {
        world,
        handles,
        stage_ms: [0.0; 6],
        points: 0,
    };
    let mut row = run(scene, &mut engine, steps);
    let per_step = |total: f64| total / f64::from(steps);
    row.profile = Some(Profile {
        stage_ms: engine.stage_ms.map(per_step),
        points: per_step(engine.points as f64),
        passes: solver.substeps * (1 + solver.iterations + solver.relax_iterations),
    });
    row
}

fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted[sorted.len() / 2]
}

fn main() {
    let args = Args::parse();
    let mut profiles = Vec::new();
    println!(
        "| scene | solver | final drift (mm) | peak drift (mm) | stands | median ms/step | mean ms/step | contact points (last step) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for name in &args.scenes {
        let scene = name.build();
        let steps = args.steps.unwrap_or(scene.steps);
        // The scene's own criterion: the stability suite's drift limit for this structure.
        let limit = match scene.check {
            SceneCheck::MaxDrift { meters } => meters,
            _ => f32::INFINITY,
        };
        for setting in SETTINGS {
            if !args.settings.is_empty() && !args.settings.contains(&setting) {
                continue;
            }
            let row = run_setting(&scene, setting, steps);
            let stands = if row.peak_drift <= limit {
                "yes".to_owned()
            } else {
                format!("no (> {:.0} mm)", limit * 1e3)
            };
            println!(
                "| {name} | {} | {:.2} | {:.2} | {stands} | {:.3} | {:.3} | {} |",
                setting.label(),
                row.final_drift * 1e3,
                row.peak_drift * 1e3,
                median(&row.ms),
                row.ms.iter().sum::<f64>() / row.ms.len() as f64,
                row.points,
            );
            if let Some(profile) = row.profile {
                profiles.push((*name, setting, profile));
            }
        }
    }
    println!();
    println!(
        "| scene | solver | aabbs | broad | narrow | color | solve | finish (mean ms/step) | points | passes | solve ns/point/pass |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for (name, setting, p) in profiles {
        let [aabbs, broad, narrow, color, solve, finish] = p.stage_ms;
        println!(
            "| {name} | {} | {aabbs:.3} | {broad:.3} | {narrow:.3} | {color:.3} | {solve:.3} | {finish:.3} | {:.0} | {} | {:.1} |",
            setting.label(),
            p.points,
            p.passes,
            p.solve_ns_per_point_pass(),
        );
    }
}
