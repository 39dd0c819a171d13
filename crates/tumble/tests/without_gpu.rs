//! The facade built without its `gpu` feature (`cargo test -p tumble --no-default-features`):
//! the CPU step runs, and the GPU backends are a clear error naming the backend and the
//! missing feature, never a panic, whatever the machine has.
#![cfg(not(feature = "gpu"))]

mod common;

use common::{assert_gpu_backends_unavailable, cube_at, floor, steps, world};

#[test]
fn gpu_backends_are_unavailable_naming_the_missing_feature() {
    assert_gpu_backends_unavailable(|backend, reason| {
        // The user learns why and what to change: the feature by name.
        assert!(reason.contains("`gpu` feature"), "{backend:?}: {reason}");
        assert!(reason.contains("Backend::Cpu"), "{backend:?}: {reason}");
    });
}

#[test]
fn the_cpu_step_runs_without_the_gpu_feature() {
    let mut world = world();
    floor(&mut world);
    let cube = cube_at(&mut world, 0.0, 2.0, 0.0);
    steps(&mut world, 120);
    // Dropped from 1.5 m above the floor, after 2 s the cube rests on it (centre at 0.5 m,
    // within the solver's centimetre of slop and penetration).
    let y = world.pose(cube).unwrap().translation.y;
    assert!((y - 0.5).abs() < 0.01, "y = {y}");
}
