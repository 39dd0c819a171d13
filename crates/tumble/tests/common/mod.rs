//! Helpers shared by the facade's test files.
#![allow(dead_code)]

use tumble::prelude::*;

pub const G: Real = 9.81;
pub const DT: Real = 1.0 / 60.0;

pub fn world() -> World {
    World::new(WorldConfig::default()).unwrap()
}

/// A fixed floor whose top face is at y = 0.
pub fn floor(world: &mut World) -> BodyHandle {
    world
        .add_body(
            BodyDesc::fixed()
                .cuboid(Vec3::new(20.0, 0.5, 20.0))
                .translation(0.0, -0.5, 0.0),
        )
        .unwrap()
}

/// Adds a unit cube (a dynamic body of the default shape) centred at `(x, y, z)`; its handle.
pub fn cube_at(world: &mut World, x: Real, y: Real, z: Real) -> BodyHandle {
    world
        .add_body(BodyDesc::dynamic().translation(x, y, z))
        .unwrap()
}

pub fn steps(world: &mut World, n: usize) {
    for _ in 0..n {
        world.step().unwrap();
    }
}

/// A world without gravity, for tests of free motion.
pub fn weightless() -> World {
    World::new(WorldConfig {
        gravity: Vec3::zeros(),
        ..Default::default()
    })
    .unwrap()
}

/// Substeps of the default soft step: damping and integration act once per substep.
pub fn substeps(world: &World) -> i32 {
    world.config().solver.substeps as i32
}

/// A world on `backend` from `config`, or `None` (with a note) when the backend needs a GPU
/// and none is available, unless `TUMBLE_REQUIRE_GPU=1` makes that a failure. Built without
/// the `gpu` feature, the GPU backends are always skipped: no GPU can be required of them.
pub fn world_on(backend: Backend, config: WorldConfig) -> Option<World> {
    match World::new(WorldConfig { backend, ..config }) {
        Ok(w) => Some(w),
        Err(e @ Error::BackendUnavailable { .. })
            if !cfg!(feature = "gpu")
                || std::env::var("TUMBLE_REQUIRE_GPU").as_deref() != Ok("1") =>
        {
            eprintln!("skipped {backend:?}: {e}");
            None
        }
        Err(e) => panic!("{backend:?}: {e}"),
    }
}

/// Asserts that `Backend::Gpu` and `Backend::Hybrid` both refuse to open, each with
/// `Error::BackendUnavailable` naming that backend (in the field and in the message) and no
/// bad field; `check_reason` then checks the reason given for each.
pub fn assert_gpu_backends_unavailable(check_reason: impl Fn(Backend, &str)) {
    for backend in [Backend::Gpu, Backend::Hybrid] {
        let err = World::new(WorldConfig {
            backend,
            ..Default::default()
        })
        .unwrap_err();
        match &err {
            Error::BackendUnavailable { backend: b, reason } => {
                assert_eq!(*b, backend);
                check_reason(backend, reason);
            }
            other => panic!("{backend:?}: expected BackendUnavailable, got {other:?}"),
        }
        // The message names the backend too, as `Display` prints it.
        assert!(err.to_string().contains(&format!("{backend:?}")), "{err}");
        assert_eq!(err.field(), None, "not a bad field: {err}");
    }
}
