//! Effects a scene does not use are compiled out of the solver pipelines through WGSL
//! `override` switches, never branched on per thread. Turning an effect off only removes work
//! whose result is known to be zero, so results do not change. Rotation is the
//! exception in the contact rows: there the angular terms are skipped per body at run time
//! (a body that cannot turn: `body_turns` in `contact_math.wgsl`) in every specialization,
//! and the switch only acts in the body passes (integration, inertia). Removing them at
//! compile time made two different programs of the same arithmetic, which a driver may round
//! differently: on an H100 they did (the reasoning is in `contact_math.wgsl`).

use tumble_geometry::Vec3;
use tumble_solver::Body;

/// Which optional parts of the solver the pipelines contain.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Effects {
    /// Friction rows (off when no contact can have a nonzero combined friction).
    pub friction: bool,
    /// The restitution pass (off when no material bounces).
    pub restitution: bool,
    /// Gravity in the velocity integration (off for zero gravity).
    pub gravity: bool,
    /// Angular terms (off when every moving body is dynamic with all rotations locked).
    pub rotation: bool,
    /// Islands and sleep ([`crate::sleep`]). Not a solver switch: a world with it off never
    /// records the sleep stage, and its solver pipelines are the same either way. Like the
    /// CPU's, it changes results (sleeping bodies stop), so it is never derived from bodies.
    pub sleep: bool,
}

impl Effects {
    /// Everything compiled in.
    pub const ALL: Self = Self {
        friction: true,
        restitution: true,
        gravity: true,
        rotation: true,
        sleep: true,
    };

    /// The effects `bodies` under `gravity` can need (sleep off): tumble-solver's derivation
    /// ([`tumble_solver::Effects::of_bodies`]), so the GPU and the CPU compile in the same.
    pub fn of_scene(bodies: &[Body], gravity: &Vec3) -> Self {
        Self::from(&tumble_solver::Effects::of_bodies(bodies, gravity))
    }

    /// The `override` values of the solver's switches (sleep has none: it is a stage).
    pub fn overrides(&self) -> [(&'static str, f64); 4] {
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        [
            ("ENABLE_FRICTION", flag(self.friction)),
            ("ENABLE_RESTITUTION", flag(self.restitution)),
            ("ENABLE_GRAVITY", flag(self.gravity)),
            ("ENABLE_ROTATION", flag(self.rotation)),
        ]
    }
}

impl From<&tumble_solver::Effects> for Effects {
    /// The switches the GPU step has (kinematic handling has none here: the GPU step always
    /// moves kinematic bodies, and its sleep stage always checks them).
    fn from(e: &tumble_solver::Effects) -> Self {
        Self {
            friction: e.friction,
            restitution: e.restitution,
            gravity: e.gravity,
            rotation: e.rotation,
            sleep: e.sleep,
        }
    }
}
