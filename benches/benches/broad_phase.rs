//! Sweep-and-prune on random boxes: 1k, 10k and 100k, with reused scratch buffers (as a world
//! calls it every step) and through the allocating free function; brute force at 1k for scale.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use tumble_broad::{SweepAndPrune, brute_force_pairs, sweep_and_prune};
use tumble_geometry::Aabb;
use tumble_tests::scene_support::sparse_boxes;

/// Boxes per cubic meter: about what a settled pile of 1 m boxes with gaps looks like, giving
/// each box a handful of overlapping neighbours (about 1.5 pairs per box).
const DENSITY: f32 = 0.3;

/// `n` boxes with half sizes in [0.05, 0.5] m, centres uniform in a cube holding `DENSITY`.
fn random_boxes(n: usize, seed: u64) -> Vec<Aabb> {
    sparse_boxes(n, (n as f32 / DENSITY).cbrt(), seed)
}

fn broad_phase(c: &mut Criterion) {
    let mut group = c.benchmark_group("broad_phase");
    for n in [1_000, 10_000, 100_000] {
        let boxes = random_boxes(n, n as u64);
        group.throughput(Throughput::Elements(n as u64));
        let mut sap = SweepAndPrune::new();
        let mut pairs = Vec::new();
        group.bench_with_input(BenchmarkId::new("sap_reused", n), &boxes, |b, boxes| {
            b.iter(|| {
                sap.find_pairs(black_box(boxes), &mut pairs);
                black_box(pairs.len())
            })
        });
        group.bench_with_input(BenchmarkId::new("sap_fresh", n), &boxes, |b, boxes| {
            b.iter(|| black_box(sweep_and_prune(black_box(boxes))).len())
        });
        if n == 1_000 {
            group.bench_with_input(BenchmarkId::new("brute_force", n), &boxes, |b, boxes| {
                b.iter(|| black_box(brute_force_pairs(black_box(boxes))).len())
            });
        }
    }
    group.finish();
}

criterion_group!(benches, broad_phase);
criterion_main!(benches);
