//! A lost GPU device, seen through the facade: every later step of a `Backend::Gpu` world on
//! it returns `Error::BackendUnavailable` naming the backend and the loss (never a panic or a
//! hang), and a world made after the loss opens a new device and simulates normally.
//!
//! In a file of its own: the facade's GPU worlds share one device per process, and this test
//! destroys it (`wgpu::Device::destroy`, the one loss wgpu lets a program cause), which must
//! not reach any other test's world.
#![cfg(feature = "gpu")]

mod common;

use common::*;
use tumble::prelude::*;

/// A floor and one unit cube dropped from 1 m, on `Backend::Gpu`; `None` when skipped.
fn dropped_cube() -> Option<(World, BodyHandle)> {
    let mut w = world_on(Backend::Gpu, WorldConfig::default())?;
    floor(&mut w);
    let cube = cube_at(&mut w, 0.0, 1.5, 0.0);
    Some((w, cube))
}

#[test]
fn a_lost_device_fails_every_step_by_name_and_a_new_world_opens_another() {
    let Some((mut world, cube)) = dropped_cube() else {
        return;
    };
    steps(&mut world, 3);
    let ctx = world
        .gpu_context()
        .expect("a Backend::Gpu world has a device");
    ctx.device.destroy();
    ctx.wait_idle().ok();
    assert!(ctx.is_lost(), "destroy must report the device lost");
    for attempt in 0..3 {
        match world.step() {
            Err(Error::BackendUnavailable { backend, reason }) => {
                assert_eq!(backend, Backend::Gpu);
                // The reason must say what happened, not only that the backend failed.
                assert!(
                    reason.to_lowercase().contains("lost"),
                    "step {attempt}: the reason must name the loss: {reason}"
                );
            }
            other => {
                panic!("step {attempt} after the loss: expected BackendUnavailable, got {other:?}")
            }
        }
        // Reading a pose after the loss either gives the last one the host holds or the
        // same error; it must not panic or hang (the call returning is the check), and a
        // pose it gives is finite.
        match world.pose(cube) {
            Ok(p) => assert!(p.translation.vector.iter().all(|x| x.is_finite())),
            Err(Error::BackendUnavailable { backend, .. }) => assert_eq!(backend, Backend::Gpu),
            Err(e) => panic!("a pose read after the loss: {e}"),
        }
    }

    // The shared device is replaced for worlds made after the loss: a new world steps, and
    // its cube lands. A unit cube dropped 1 m comes to rest with its centre at its half
    // height of 0.5 m; 2 s is long enough to land and settle, and 1 cm is the penetration
    // slop plus margin, far below the 1 m the cube fell.
    let (mut fresh, cube) = dropped_cube().expect("a Backend::Gpu world opens after the loss");
    let new_ctx = fresh.gpu_context().expect("a device");
    assert!(
        !new_ctx.is_lost(),
        "the new world must not be on the lost device"
    );
    steps(&mut fresh, 120);
    let y = fresh.pose(cube).unwrap().translation.vector.y;
    assert!(
        (y - 0.5).abs() < 0.01,
        "the cube rests at y = {y}, expected 0.5"
    );
}
