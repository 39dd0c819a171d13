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

/// `#[test] fn $name` running `$check` on the GPU backend's config with `$gravity`; without
/// an adapter it does nothing (after [`GpuContext::for_tests`]'s loud "skipped").
macro_rules! gpu_tests {
    ($($name:ident($gravity:expr) => $check:expr;)+) => {
        $(
            #[test]
            fn $name() {
                let check: fn(WorldConfig) = $check;
                if let Some(base) = gpu_config($gravity) {
                    check(base);
                }
            }
        )+
    };
}

gpu_tests! {
    friction_skipped_in_a_frictionless_pool(G) => |base| FRICTION.same_bits_on_and_off(base);
    restitution_skipped_when_nothing_bounces(G) => |base| RESTITUTION.same_bits_on_and_off(base);
    gravity_skipped_in_zero_gravity(Vec3::zeros()) => |base| GRAVITY.same_bits_on_and_off(base);
    rotation_skipped_when_every_rotation_is_locked(G) =>
        |base| ROTATION.same_bits_on_and_off(base);
}

// The other side on the GPU step (the facade's path: the fused solver on a small scene;
// gpu_wide_effects.rs checks the wide one): the same scenes and bounds as on the CPU.
// Kinematic handling has no GPU switch (its sleep stage always checks kinematic bodies).

gpu_tests! {
    friction_forced_off_lets_a_thrown_cube_slide_on(G) => check_friction;
    restitution_forced_off_stops_the_bounce(G) => check_restitution;
    gravity_forced_off_leaves_a_cube_in_the_air(G) => check_gravity;
    sleep_forced_off_lets_a_creeping_cube_creep_on(G) => check_sleep;
    rotation_forced_off_keeps_a_tipped_cube_from_turning(G) => check_tipped_cube;
}
