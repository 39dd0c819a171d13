//! The wide solver path names each per-color dispatch's color with immediate data on a
//! device that has it (`solve_color_immediate`, one bind group per pass) and with a uniform
//! bound per color elsewhere (`solve_color`, one bind group per color). The two kernels share
//! their body; the host only records the color differently. This pins that the two give the
//! same bits, on every dispatch form a sweep records: colors one by one (indirect), the tail
//! that takes the remaining colors in one thread, and the overflow set alone after the
//! per-body warm start.
//!
//! Needs a GPU (or lavapipe): without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure. A device without
//! immediate data is skipped too (loudly): it has only one of the two forms to compare.

use tumble_geometry::{Cuboid, Pose, Real, Vec3};
use tumble_gpu::solver::{SolvePath, WarmStartSweep};
use tumble_gpu::step::{ColorDispatch, GpuWorld, GpuWorldConfig, PathPolicy, ReadRequest};
use tumble_gpu::{GpuContext, GpuOptions};
use tumble_solver::{Body, BodyKind, BodyState, Material};
use tumble_tests::gpu_solver_util::{floor, pose_bits, velocity_bits};

/// Steps per run: the plate falls 0.3 m, lands tilted on the cubes and rocks (about 0.25 s
/// of falling, then contact), so the coloring changes from step to step.
const STEPS: usize = 40;

/// A 6.4 m plate held 0.3 m above a 6 x 6 grid of spaced cubes, tilted: once it lands it
/// touches all 36 cubes, more constraints on one body than the 24 graph colors, so at least
/// 12 go to the overflow set every step.
fn falling_plate() -> (Vec<Body>, Vec<BodyState>) {
    let mut bodies = vec![floor(Material::default())];
    for i in 0..6 {
        for j in 0..6 {
            bodies.push(
                Body::new(
                    BodyKind::Dynamic,
                    Cuboid::new(Vec3::repeat(0.25)),
                    Pose::translation(i as Real - 2.5, 0.25, j as Real - 2.5),
                    1.0,
                    Material::default(),
                )
                .unwrap(),
            );
        }
    }
    bodies.push(
        Body::new(
            BodyKind::Dynamic,
            Cuboid::new(Vec3::new(3.2, 0.1, 3.2)),
            Pose::new(Vec3::new(0.0, 0.92, 0.0), Vec3::new(0.03, 0.0, -0.02)),
            2.0,
            Material::default(),
        )
        .unwrap(),
    );
    let states = vec![BodyState::default(); bodies.len()];
    (bodies, states)
}

/// The bits of every pose and velocity after [`STEPS`] steps of the falling plate on `ctx`,
/// wide path, the first two colors dispatched one by one (the rest in each pass's tail),
/// the warm start by `warm_start_sweep`.
fn run(ctx: &GpuContext, warm_start_sweep: WarmStartSweep) -> Vec<u32> {
    let (bodies, states) = falling_plate();
    let config = GpuWorldConfig {
        path: PathPolicy::Always(SolvePath::Wide),
        color_dispatch: ColorDispatch::First(2),
        warm_start_sweep,
        ..Default::default()
    };
    let mut world = GpuWorld::new(ctx, config).unwrap();
    world.set_bodies(&bodies, &states).unwrap();
    for _ in 0..STEPS {
        world.step().unwrap();
    }
    let snapshot = world.read_now(ReadRequest::MOTION).unwrap();
    // The plate (last body) landed and stays on the cubes: its centre within 3 cm of the
    // 0.6 m it rests at (cube tops at 0.5 m plus its half thickness). Still at 0.92 m it
    // never fell; far below, the overflow set (most of its contacts) went unsolved.
    let y = snapshot.poses.last().unwrap().position[1];
    assert!((y - 0.6).abs() < 0.03, "plate centre at y = {y}");
    let poses = snapshot.poses.iter().flat_map(pose_bits);
    poses
        .chain(snapshot.velocities.iter().flat_map(velocity_bits))
        .collect()
}

#[test]
fn the_color_as_immediate_data_gives_the_bits_of_a_uniform_per_color() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    if !ctx.has_immediates {
        eprintln!(
            "##### skipped: {} has no immediate data, only the uniform form to compare #####",
            ctx.info.name
        );
        return;
    }
    // The same adapter with an immediate-data limit of 0 opens without the feature and
    // binds a uniform per color.
    let uniform = GpuContext::with_options(&GpuOptions {
        adapter_name: Some(ctx.info.name.clone()),
        limits: Some(tumble_gpu::wgpu::Limits {
            max_immediate_size: 0,
            ..ctx.adapter.limits()
        }),
        ..Default::default()
    })
    .unwrap();
    assert!(!uniform.has_immediates, "a limit of 0 still opened it");
    // The per-body warm start leaves the overflow set to a dispatch of its own; the other
    // passes sweep the colors (two one by one, then the tail). The colored warm start is
    // the same sweep again, left out to keep the test short.
    let a = run(&ctx, WarmStartSweep::PerBody);
    let b = run(&uniform, WarmStartSweep::PerBody);
    assert_eq!(a.len(), b.len());
    let first = a.iter().zip(&b).position(|(x, y)| x != y);
    assert_eq!(
        first, None,
        "immediate and uniform colors differ at word {first:?}"
    );
}
