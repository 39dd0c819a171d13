//! The facade built without its `gpu` feature (`cargo test -p tumble --no-default-features`):
//! the CPU step runs, and the GPU backends are a clear error naming the backend and the
//! missing feature, never a panic, whatever the machine has.
#![cfg(not(feature = "gpu"))]

use tumble::prelude::*;

#[test]
fn gpu_backends_are_unavailable_naming_the_missing_feature() {
    for backend in [Backend::Gpu, Backend::Hybrid] {
        let err = World::new(WorldConfig {
            backend,
            ..Default::default()
        })
        .unwrap_err();
        match &err {
            Error::BackendUnavailable { backend: b, reason } => {
                assert_eq!(*b, backend);
                // The user learns why and what to change: the feature by name.
                assert!(reason.contains("`gpu` feature"), "{backend:?}: {reason}");
                assert!(reason.contains("Backend::Cpu"), "{backend:?}: {reason}");
            }
            other => panic!("{backend:?}: expected BackendUnavailable, got {other:?}"),
        }
        // The message names the backend too, as `Display` prints it.
        assert!(err.to_string().contains(&format!("{backend:?}")), "{err}");
        assert_eq!(err.field(), None, "not a bad field: {err}");
    }
}

#[test]
fn the_cpu_step_runs_without_the_gpu_feature() {
    let mut world = World::new(WorldConfig::default()).unwrap();
    world
        .add_body(
            BodyDesc::fixed()
                .cuboid(Vec3::new(5.0, 0.5, 5.0))
                .translation(0.0, -0.5, 0.0),
        )
        .unwrap();
    let cube = world
        .add_body(BodyDesc::dynamic().translation(0.0, 2.0, 0.0))
        .unwrap();
    for _ in 0..120 {
        world.step().unwrap();
    }
    // Dropped from 1.5 m above the floor, after 2 s the cube rests on it (centre at 0.5 m,
    // within the solver's centimetre of slop and penetration).
    let y = world.pose(cube).unwrap().translation.y;
    assert!((y - 0.5).abs() < 0.01, "y = {y}");
}
