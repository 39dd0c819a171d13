//! `cargo xtask validate --batch`: the grid's Tumble runs of each scene and backend again, as
//! one `WorldBatch` (one world per configuration), timed against the same runs one by one and
//! checked bit for bit against them.
//!
//! The one-by-one time of a run is its wall time in the grid (building the world, stepping,
//! reading every body's state after every step, the scene's check); the batch's is the wall
//! time of building the batch, stepping it and reading every world's poses and velocities
//! after every step. Each world's final poses and velocities must equal, bit for bit, those
//! of the same configuration run alone: the batch steps each world with the single world's
//! arithmetic (on `Backend::Gpu`, one device world per distinct configuration).

use std::time::Instant;

use tumble::scenes::Scene;
use tumble::{EffectOverrides, POSE_FLOATS, VELOCITY_FLOATS, WorldBatch, WorldConfig, WorldSpec};

use crate::engine::BodyState;
use crate::engine_tumble::{backend, solver_config};
use crate::grid::{BackendChoice, RunConfig, TumbleSetting};

/// One grid run that a batch repeats: its scene, setting, steps, wall time and final states.
pub struct Done {
    pub scene: usize,
    pub setting: TumbleSetting,
    pub steps: u32,
    pub wall_s: f64,
    pub last: Vec<BodyState>,
}

impl Done {
    /// The run of `config` when it is a Tumble grid run.
    pub fn of(
        scene: usize,
        config: &RunConfig,
        steps: u32,
        wall_s: f64,
        last: &[BodyState],
    ) -> Option<Self> {
        match config {
            RunConfig::Tumble(setting) => Some(Self {
                scene,
                setting: *setting,
                steps,
                wall_s,
                last: last.to_vec(),
            }),
            RunConfig::Rapier { .. } => None,
        }
    }
}

/// One batch's result.
struct Row {
    scene: String,
    backend: BackendChoice,
    worlds: usize,
    device_worlds: usize,
    steps: u32,
    alone_s: f64,
    batch_s: f64,
    equal: usize,
    error: Option<String>,
}

fn bits(states: &[BodyState]) -> Vec<u32> {
    states
        .iter()
        .flat_map(|s| {
            let (t, q) = (s.pose.translation.vector, s.pose.rotation.coords);
            [t.x, t.y, t.z, q.x, q.y, q.z, q.w]
                .into_iter()
                .chain(s.linear_velocity.iter().copied())
                .chain(s.angular_velocity.iter().copied())
                .map(f32::to_bits)
                .collect::<Vec<_>>()
        })
        .collect()
}

/// Runs `runs` of one scene and backend (all of `steps` steps) as one batch; the time and
/// how many worlds ended equal to their runs alone.
fn run_batch(scene: &Scene, runs: &[&Done]) -> Result<(f64, usize, usize), String> {
    let steps = runs[0].steps;
    let started = Instant::now();
    let specs = runs
        .iter()
        .map(|r| {
            let config = WorldConfig {
                solver: solver_config(&r.setting),
                backend: backend(r.setting.backend),
                effects: EffectOverrides::NO_SLEEP,
                ..Default::default()
            };
            WorldSpec::from_scene(scene, config)
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?;
    let mut batch = WorldBatch::from_specs(backend(runs[0].setting.backend), specs)
        .map_err(|e| e.to_string())?;
    let mut poses = vec![0.0f32; batch.all_poses_len()];
    let mut velocities = vec![0.0f32; batch.all_velocities_len()];
    for _ in 0..steps {
        batch.step().map_err(|e| e.to_string())?;
        batch
            .read_all_poses(&mut poses)
            .map_err(|e| e.to_string())?;
        batch
            .read_all_velocities(&mut velocities)
            .map_err(|e| e.to_string())?;
    }
    let elapsed = started.elapsed().as_secs_f64();
    let n = scene.bodies.len();
    let mut equal = 0;
    for (k, run) in runs.iter().enumerate() {
        let mine: Vec<u32> = (0..n)
            .flat_map(|b| {
                let i = k * n + b;
                poses[i * POSE_FLOATS..(i + 1) * POSE_FLOATS]
                    .iter()
                    .chain(&velocities[i * VELOCITY_FLOATS..(i + 1) * VELOCITY_FLOATS])
                    .map(|x| x.to_bits())
                    .collect::<Vec<_>>()
            })
            .collect();
        if mine == bits(&run.last) {
            equal += 1;
        }
    }
    Ok((elapsed, equal, batch.device_worlds()))
}

/// Runs every scene's grid runs again as batches (per scene, backend and step count) and
/// returns the markdown of the comparison, and whether every world matched its run alone.
pub fn run_batches(scenes: &[Scene], done: &[Done]) -> (String, bool) {
    let mut rows = Vec::new();
    for (i, scene) in scenes.iter().enumerate() {
        for choice in [
            BackendChoice::Cpu,
            BackendChoice::Gpu,
            BackendChoice::Hybrid,
        ] {
            let mut lengths: Vec<u32> = done
                .iter()
                .filter(|d| d.scene == i && d.setting.backend == choice)
                .map(|d| d.steps)
                .collect();
            lengths.sort_unstable();
            lengths.dedup();
            for steps in lengths {
                let runs: Vec<&Done> = done
                    .iter()
                    .filter(|d| d.scene == i && d.setting.backend == choice && d.steps == steps)
                    .collect();
                let alone_s: f64 = runs.iter().map(|r| r.wall_s).sum();
                let (batch_s, equal, device_worlds, error) = match run_batch(scene, &runs) {
                    Ok((t, e, d)) => (t, e, d, None),
                    Err(e) => (0.0, 0, 0, Some(e)),
                };
                rows.push(Row {
                    scene: scene.name.clone(),
                    backend: choice,
                    worlds: runs.len(),
                    device_worlds,
                    steps,
                    alone_s,
                    batch_s,
                    equal,
                    error,
                });
            }
        }
    }
    let mut md = String::from(
        "| scene | backend | configurations | device worlds | steps | one by one (s) | as one batch (s) | speed-up | worlds equal to their run alone |\n|---|---|---:|---:|---:|---:|---:|---:|---|\n",
    );
    let (mut alone, mut batched) = (0.0, 0.0);
    let mut all_equal = true;
    for r in &rows {
        alone += r.alone_s;
        batched += r.batch_s;
        all_equal &= r.error.is_none() && r.equal == r.worlds;
        let equal = match &r.error {
            Some(e) => format!("failed: {e}"),
            None => format!("{} of {}", r.equal, r.worlds),
        };
        md.push_str(&format!(
            "| {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.2} | {} |\n",
            r.scene,
            r.backend.name(),
            r.worlds,
            r.device_worlds,
            r.steps,
            r.alone_s,
            r.batch_s,
            if r.batch_s > 0.0 {
                r.alone_s / r.batch_s
            } else {
                0.0
            },
            equal
        ));
    }
    md.push_str(&format!(
        "\nIn all: {alone:.1} s one by one, {batched:.1} s as batches, speed-up {:.2}; {}.\n",
        if batched > 0.0 { alone / batched } else { 0.0 },
        if all_equal {
            "every world ended bit for bit as its run alone"
        } else {
            "SOME WORLDS DIFFER from their runs alone"
        }
    ));
    (md, all_equal)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::Engine;
    use crate::engine_tumble::{TumbleEngine, default_setting};
    use tumble::scenes::builders;

    /// Two settings of a short column, run alone as the grid runs them: the batch of the two
    /// must end bit for bit where each ended alone (a world stepped twice, or with the other's
    /// settings, would not).
    #[test]
    fn a_batch_of_grid_runs_ends_where_each_run_ended_alone() {
        let scene = builders::stack(4);
        let settings = [
            default_setting(),
            TumbleSetting {
                substeps: 2,
                is_default: false,
                ..default_setting()
            },
        ];
        let steps = 40;
        let done: Vec<Done> = settings
            .iter()
            .map(|s| {
                let mut engine = TumbleEngine::new(&scene, s).unwrap();
                for _ in 0..steps {
                    engine.step().unwrap();
                }
                let mut last = Vec::new();
                engine.read_states(&mut last);
                Done::of(0, &RunConfig::Tumble(*s), steps, 1.0, &last).unwrap()
            })
            .collect();
        // The two runs differ, so matching each one's bits means something.
        assert_ne!(bits(&done[0].last), bits(&done[1].last));
        let (md, equal) = run_batches(&[scene], &done);
        assert!(equal, "{md}");
        assert!(md.contains("| 2 of 2 |"), "{md}");
    }
}
