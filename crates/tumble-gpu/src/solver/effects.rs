//! Effects a scene does not use are compiled out of the solver pipelines through WGSL
//! `override` switches, never branched on per thread. Turning an effect off only removes work
//! whose result is known to be zero, so results do not change. Rotation is the
//! exception in the contact rows: there the angular terms are skipped per body at run time
//! (a body that cannot turn: `body_turns` in `contact_math.wgsl`) in every specialization,
//! and the switch only acts in the body passes (integration, inertia). Removing them at
//! compile time made two different programs of the same arithmetic, which a driver may round
//! differently: on an H100 they did (the reasoning is in `contact_math.wgsl`).
//!
//! The effects are tumble-solver's [`Effects`], derived from the bodies as the CPU step
//! derives them, so the GPU and the CPU compile in the same. Two of its fields are no solver
//! switch here: `sleep` is a stage ([`crate::sleep`]) that a world records or not, and
//! `kinematic` has no switch (the GPU step always moves kinematic bodies, and its sleep stage
//! always checks them). Neither reaches [`effect_overrides`], so pipelines never differ by
//! them.

pub use tumble_solver::Effects;

/// The `override` values of the solver's switches for `effects`, by WGSL name.
pub fn effect_overrides(effects: &Effects) -> [(&'static str, f64); 4] {
    let flag = |on: bool| if on { 1.0 } else { 0.0 };
    [
        ("ENABLE_FRICTION", flag(effects.friction)),
        ("ENABLE_RESTITUTION", flag(effects.restitution)),
        ("ENABLE_GRAVITY", flag(effects.gravity)),
        ("ENABLE_ROTATION", flag(effects.rotation)),
    ]
}
