//! The same contract on the GPU step, whose pipelines are specialized per effect set
//! (`override` switches): its step is deterministic, so forced on and skipped give the same
//! bits there too. Needs a GPU or lavapipe; without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`.

use super::forced_off::{
    check_friction, check_gravity, check_restitution, check_sleep, check_tipped_cube,
};
use super::skipped::{FRICTION, GRAVITY, RESTITUTION, ROTATION};
use super::*;
use tumble_gpu::GpuContext;

/// The GPU backend's config with `gravity`, or `None` without an adapter.
fn gpu_config(gravity: Vec3) -> Option<WorldConfig> {
    GpuContext::for_tests()?;
    Some(WorldConfig {
        backend: Backend::Gpu,
        gravity,
        ..Default::default()
    })
}

const G: Vec3 = Vec3::new(0.0, -tumble::STANDARD_GRAVITY, 0.0);

#[test]
fn friction_skipped_in_a_frictionless_pool() {
    if let Some(base) = gpu_config(G) {
        FRICTION.same_bits_on_and_off(base);
    }
}

#[test]
fn restitution_skipped_when_nothing_bounces() {
    if let Some(base) = gpu_config(G) {
        RESTITUTION.same_bits_on_and_off(base);
    }
}

#[test]
fn gravity_skipped_in_zero_gravity() {
    if let Some(base) = gpu_config(Vec3::zeros()) {
        GRAVITY.same_bits_on_and_off(base);
    }
}

#[test]
fn rotation_skipped_when_every_rotation_is_locked() {
    if let Some(base) = gpu_config(G) {
        ROTATION.same_bits_on_and_off(base);
    }
}

// The other side on the GPU step (the facade's path: the fused solver on a small scene;
// gpu_wide_effects.rs checks the wide one): the same scenes and bounds as on the CPU.
// Kinematic handling has no GPU switch (its sleep stage always checks kinematic bodies).

#[test]
fn friction_forced_off_lets_a_thrown_cube_slide_on() {
    if let Some(base) = gpu_config(G) {
        check_friction(base);
    }
}

#[test]
fn restitution_forced_off_stops_the_bounce() {
    if let Some(base) = gpu_config(G) {
        check_restitution(base);
    }
}

#[test]
fn gravity_forced_off_leaves_a_cube_in_the_air() {
    if let Some(base) = gpu_config(G) {
        check_gravity(base);
    }
}

#[test]
fn sleep_forced_off_lets_a_creeping_cube_creep_on() {
    if let Some(base) = gpu_config(G) {
        check_sleep(base);
    }
}

#[test]
fn rotation_forced_off_keeps_a_tipped_cube_from_turning() {
    if let Some(base) = gpu_config(G) {
        check_tipped_cube(base);
    }
}
