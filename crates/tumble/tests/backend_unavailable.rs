//! `Error::BackendUnavailable`, reached without depending on the machine: the adapter named by
//! `TUMBLE_ADAPTER` matches no adapter, so `Backend::Gpu` and `Backend::Hybrid` cannot open a
//! device whether or not the machine has a GPU, while `Backend::Cpu` never looks for one.
//!
//! The world opens one device per process, on first use, reading the variable then; this
//! file's single test sets it before any world exists, in a process of its own.
//!
//! Built without the `gpu` feature the GPU backends never look for an adapter: `without_gpu.rs`
//! covers that build.
#![cfg(feature = "gpu")]

mod common;

use common::assert_gpu_backends_unavailable;
use tumble::prelude::*;
use tumble_gpu::context::ADAPTER_ENV;

/// No adapter's name contains this.
const NO_SUCH_ADAPTER: &str = "no-adapter-is-called-this-4f1c";

#[test]
fn a_gpu_backend_with_an_adapter_that_matches_nothing_is_unavailable() {
    // SAFETY: the only test of this binary, run before any thread of it reads the environment
    // (no world or device exists yet).
    unsafe { std::env::set_var(ADAPTER_ENV, NO_SUCH_ADAPTER) };
    assert_gpu_backends_unavailable(|backend, reason| {
        // The reason names what was asked for, so the user sees why.
        assert!(reason.contains(NO_SUCH_ADAPTER), "{backend:?}: {reason}");
        assert!(reason.contains(ADAPTER_ENV), "{backend:?}: {reason}");
    });
    // The CPU backend opens no device, so the same setting cannot make it unavailable.
    let mut world = World::new(WorldConfig::default()).unwrap();
    let b = world.add_body(BodyDesc::dynamic()).unwrap();
    world.step().unwrap();
    assert!(
        world.linear_velocity(b).unwrap().y < 0.0,
        "the CPU world runs"
    );
}
