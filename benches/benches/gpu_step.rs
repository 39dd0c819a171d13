//! The whole step on the GPU (`tumble_gpu::step::GpuWorld`: collision and solver stages in one
//! command encoder per step), with the wide and the fused solver path side by side, on
//! pyramids of growing height. Each scene first runs 60 steps so warm starts and color seeds
//! are settled; per-stage GPU times (timestamp queries, when the device has them) are printed
//! once per scene and path.
//!
//! `cargo bench -p tumble-benches --bench gpu_step` (needs a GPU or lavapipe; without one it
//! prints that it skipped).

use criterion::{Criterion, criterion_group, criterion_main};
use tumble_benches::bodies_of;
use tumble_geometry::Vec3;
use tumble_gpu::GpuContext;
use tumble_gpu::solver::SolvePath;
use tumble_gpu::step::{GpuWorld, GpuWorldConfig, PathPolicy};

/// Steps run before measuring: one second at 60 Hz.
const SETTLE_STEPS: usize = 60;

/// Pyramid heights: 30, 204, 650 and 2,870 cubes.
const HEIGHTS: [usize; 4] = [4, 8, 12, 20];

fn gpu_step(c: &mut Criterion) {
    let ctx = match GpuContext::new() {
        Ok(ctx) => ctx,
        Err(e) => {
            eprintln!("##### gpu_step skipped: no GPU adapter ({e}) #####");
            return;
        }
    };
    eprintln!("device: {} ({:?})", ctx.info.name, ctx.info.backend);
    let mut group = c.benchmark_group("gpu_step");
    group.sample_size(10);
    for h in HEIGHTS {
        let scene = tumble_scenes::pyramid(h);
        let (bodies, states) = bodies_of(&scene);
        for path in [SolvePath::Wide, SolvePath::Fused] {
            let mut world = GpuWorld::new(
                &ctx,
                GpuWorldConfig {
                    gravity: Vec3::from(scene.gravity),
                    dt: scene.dt,
                    path: PathPolicy::Always(path),
                    timestamps: true,
                    ..Default::default()
                },
            )
            .expect("world");
            world.set_bodies(&bodies, &states).expect("upload");
            for _ in 0..SETTLE_STEPS {
                world.step().expect("step");
            }
            let stages = world.timings().expect("timings");
            let line: Vec<String> = stages
                .iter()
                .map(|(name, s)| format!("{name} {:.3} ms", s * 1e3))
                .collect();
            eprintln!(
                "pyramid {h} ({} bodies) {path:?}: {}",
                bodies.len(),
                line.join(", ")
            );
            group.bench_function(format!("pyramid_{h}/{path:?}"), |b| {
                b.iter(|| {
                    world.step().expect("step");
                    ctx.wait_idle().expect("wait");
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, gpu_step);
criterion_main!(benches);
