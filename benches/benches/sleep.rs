//! A step of a pool of 1,000 cubes awake beside the same pool asleep.
//!
//! ```sh
//! cargo bench -p tumble-benches --bench sleep
//! ```
//!
//! Both worlds drop the cubes and step until the sleeping one has put every cube to sleep
//! (the awake one, with sleep off, has then settled the same way); the timed iterations keep
//! stepping them. Once asleep, a step skips the narrow phase and the solver entirely.

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use tumble::EffectOverrides;
use tumble_benches::effect_pool::{PoolOptions, effect_pool, with_sleep};

/// Cubes in the pool.
const CUBES: usize = 1000;
/// Most steps to wait for the pool to sleep (30 s at 60 Hz); a pool that takes longer is a
/// bug, and the bench stops rather than time an awake pool as "asleep".
const MAX_SETTLE_STEPS: usize = 1800;
/// Criterion's smallest sample count; an awake step takes milliseconds.
const SAMPLES: usize = 10;
/// Time criterion spends measuring each bench.
const MEASUREMENT_TIME: Duration = Duration::from_secs(3);

fn sleep_bench(c: &mut Criterion) {
    let options = PoolOptions {
        cubes: CUBES,
        ..Default::default()
    };
    let mut asleep = effect_pool(options, with_sleep());
    let mut awake = effect_pool(options, EffectOverrides::default());
    let mut steps = 0;
    while asleep.sleeping_count() < CUBES {
        assert!(steps < MAX_SETTLE_STEPS, "the pool did not fall asleep");
        asleep.step().expect("a valid world steps");
        awake.step().expect("a valid world steps");
        steps += 1;
    }
    let mut group = c.benchmark_group("pool1000_step");
    group.sample_size(SAMPLES);
    group.measurement_time(MEASUREMENT_TIME);
    group.bench_function("awake", |b| {
        b.iter(|| awake.step().expect("a valid world steps"))
    });
    group.bench_function("asleep", |b| {
        b.iter(|| asleep.step().expect("a valid world steps"))
    });
    group.finish();
}

criterion_group!(benches, sleep_bench);
criterion_main!(benches);
