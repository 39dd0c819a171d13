//! Wall time of the GPU collision stages per step (record, submit, wait), with and without
//! reading back the contacts, on seeded random piles. Per-stage GPU times come from
//! `src/bin/collision_stage_times.rs`, which reads the timestamp queries.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use tumble_benches::random_pile;
use tumble_gpu::{CollisionConfig, GpuCollision, GpuContext, ReadbackRequest};

fn collision_step(c: &mut Criterion) {
    let Ok(ctx) = GpuContext::new() else {
        eprintln!("##### skipped: no GPU adapter #####");
        return;
    };
    let mut group = c.benchmark_group(format!("gpu_collision/{}", ctx.info.name));
    group.sample_size(20);
    for n in [1000usize, 20_000] {
        let (poses, velocities, shapes) = random_pile::random_pile(n, 42);
        let mut gpu = GpuCollision::new(&ctx, CollisionConfig::default()).expect("pipelines");
        gpu.set_bodies(&poses, &velocities, &shapes).expect("scene");
        // Grow the pair buffers once, outside the timing.
        gpu.step_and_read(ReadbackRequest::CONTACTS).expect("step");
        group.bench_with_input(BenchmarkId::new("step", n), &n, |b, _| {
            b.iter(|| {
                gpu.step().expect("step");
                ctx.wait_idle().expect("device");
            })
        });
        group.bench_with_input(BenchmarkId::new("step_and_read_contacts", n), &n, |b, _| {
            b.iter(|| gpu.step_and_read(ReadbackRequest::CONTACTS).expect("step"))
        });
    }
    group.finish();
}

criterion_group!(benches, collision_step);
criterion_main!(benches);
