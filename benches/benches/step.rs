//! One full step of a resting pyramid: Tumble's CPU backend and rapier3d in the same group,
//! at matched substeps.
//!
//! ```sh
//! cargo bench -p tumble-benches --bench step
//! ```
//!
//! Groups:
//! - `step_pyramid12` (650 cubes): Tumble's soft step at 1, 2, 4 and 8 substeps, the Baumgarte
//!   solver at 5, 40 (its default) and 150 (the thesis's CPU count) iterations, and rapier at 1,
//!   2, 4 and 8 solver iterations (the substeps of its soft-step solver);
//! - `step_pyramid24` (4,900 cubes): the defaults of both engines (4 substeps each).
//!
//! Both groups also time rapier doing the work Tumble does (`rapier_like_tumble`): Coulomb
//! friction at every point instead of rapier's default per-manifold friction with a twist row,
//! and no contact recycling, so the narrow phase runs on every pair every step.
//!
//! Each world is built once and stepped [`WARMUP_STEPS`] times before timing, so that contacts,
//! warm-start impulses and scratch buffers exist; the timed iterations keep stepping the same
//! world, as a game loop does. Sample counts are small so the whole bench runs in minutes.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkGroup, BenchmarkId, Criterion, SamplingMode, criterion_group};
use criterion::{criterion_main, measurement::WallTime};
use rapier3d::prelude::FrictionModel;
use tumble::prelude::*;
use tumble_scenes::{RapierOptions, Scene, build_rapier_with, pyramid};

/// Steps before timing: the pyramid settles into contact (the first steps build every manifold
/// from nothing and grow the solver's buffers), and warm starting has impulses to start from.
const WARMUP_STEPS: usize = 30;
/// Criterion's smallest sample count: a 4,900-cube step takes a fraction of a second, so more
/// samples would stretch the run past minutes without changing the median.
const SAMPLES: usize = 10;
/// Time criterion spends measuring each bench (it runs over when one sample takes longer).
const MEASUREMENT_TIME: Duration = Duration::from_secs(3);
/// Criterion's own warm-up after ours: long enough to estimate the iteration time.
const CRITERION_WARM_UP: Duration = Duration::from_millis(500);

fn tumble_world(scene: &Scene, solver: SolverConfig) -> World {
    let config = WorldConfig {
        solver,
        ..WorldConfig::default()
    };
    let (mut world, _) = World::from_scene(scene, config).expect("canonical scenes are valid");
    for _ in 0..WARMUP_STEPS {
        world.step().expect("a valid world steps");
    }
    world
}

fn bench_tumble(
    group: &mut BenchmarkGroup<'_, WallTime>,
    scene: &Scene,
    name: &str,
    parameter: u32,
    solver: SolverConfig,
) {
    let mut world = tumble_world(scene, solver);
    group.bench_function(BenchmarkId::new(name, parameter), |b| {
        b.iter(|| world.step().expect("a valid world steps"))
    });
    black_box(world.stats().contact_points);
}

/// Rapier's defaults that do less work per step than Tumble does, switched off one by one
/// in the `rapier_like_tumble` rows to show how much of the gap each accounts for.
#[derive(Clone, Copy)]
enum RapierWork {
    /// Rapier's defaults: one friction constraint plus a twist row per manifold, and contact
    /// recycling (pairs that moved less than 5 cm keep last step's points).
    Default,
    /// Coulomb friction at every point (two rows per point, as Tumble solves) and every
    /// manifold recomputed every step (as Tumble's narrow phase does).
    LikeTumble,
}

fn bench_rapier(
    group: &mut BenchmarkGroup<'_, WallTime>,
    scene: &Scene,
    iterations: u32,
    work: RapierWork,
) {
    let options = RapierOptions {
        solver_iterations: iterations as usize,
        ..RapierOptions::default()
    };
    let mut world = build_rapier_with(scene, &options);
    let name = match work {
        RapierWork::Default => "rapier",
        RapierWork::LikeTumble => {
            let params = &mut world.integration_parameters;
            params.friction_model = FrictionModel::Coulomb;
            params.contact_recycling = false;
            "rapier_like_tumble"
        }
    };
    for _ in 0..WARMUP_STEPS {
        world.step();
    }
    group.bench_function(BenchmarkId::new(name, iterations), |b| {
        b.iter(|| world.step())
    });
    black_box(world.body_poses().len());
}

fn soft_step(substeps: u32) -> SolverConfig {
    SolverConfig {
        substeps,
        ..SolverConfig::soft_step()
    }
}

fn baumgarte(iterations: u32) -> SolverConfig {
    SolverConfig {
        iterations,
        ..SolverConfig::baumgarte()
    }
}

fn configure(group: &mut BenchmarkGroup<'_, WallTime>) {
    group
        .sample_size(SAMPLES)
        .measurement_time(MEASUREMENT_TIME)
        .warm_up_time(CRITERION_WARM_UP)
        // One step is milliseconds to a fraction of a second: flat sampling runs the same number
        // of steps per sample instead of a linear ramp that would multiply the run time.
        .sampling_mode(SamplingMode::Flat);
}

/// Both engines at `substeps`: tumble's soft step and rapier's default work.
fn bench_defaults(group: &mut BenchmarkGroup<'_, WallTime>, scene: &Scene, substeps: u32) {
    bench_tumble(
        group,
        scene,
        "tumble_softstep",
        substeps,
        soft_step(substeps),
    );
    bench_rapier(group, scene, substeps, RapierWork::Default);
}

/// The 650-cube pyramid at every solver setting of the comparison table.
fn pyramid12(c: &mut Criterion) {
    let scene = pyramid(12);
    let mut group = c.benchmark_group("step_pyramid12");
    configure(&mut group);
    for substeps in [1, 2, 4, 8] {
        bench_defaults(&mut group, &scene, substeps);
    }
    let substeps = SolverConfig::default().substeps;
    bench_rapier(&mut group, &scene, substeps, RapierWork::LikeTumble);
    for iterations in [5, 40, 150] {
        bench_tumble(
            &mut group,
            &scene,
            "tumble_baumgarte",
            iterations,
            baumgarte(iterations),
        );
    }
    group.finish();
}

/// The 4,900-cube pyramid at both engines' defaults.
fn pyramid24(c: &mut Criterion) {
    let scene = pyramid(24);
    let mut group = c.benchmark_group("step_pyramid24");
    configure(&mut group);
    let substeps = SolverConfig::default().substeps;
    bench_defaults(&mut group, &scene, substeps);
    bench_rapier(&mut group, &scene, substeps, RapierWork::LikeTumble);
    group.finish();
}

criterion_group!(benches, pyramid12, pyramid24);
criterion_main!(benches);
