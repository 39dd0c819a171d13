//! World settings: gravity, time step, solver, backend.

use tumble_geometry::{Real, Vec3};

use crate::EffectOverrides;
use tumble_solver::{InvalidParameter, SolverConfig, bounds};

/// Where the step runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Backend {
    /// Every stage on the CPU (the reference).
    Cpu,
    /// Every stage on the GPU through wgpu.
    Gpu,
    /// Collision (AABBs, broad and narrow phase) on the GPU, the solver on the CPU: the
    /// thesis's fastest mix.
    Hybrid,
}

/// Standard gravity, m/s^2.
pub const STANDARD_GRAVITY: Real = 9.81;

/// Box2D's speculative distance, `4 * linearSlop = 2 cm`: contacts closer than this are
/// created before the boxes touch, so a resting contact never blinks in and out.
pub const DEFAULT_MARGIN: Real = 0.02;

/// Everything a world needs besides its bodies.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WorldConfig {
    /// Gravity acceleration, m/s^2.
    pub gravity: Vec3,
    /// Step length, s.
    pub dt: Real,
    /// Solver settings.
    pub solver: SolverConfig,
    /// Where the step runs.
    pub backend: Backend,
    /// Base speculative margin, m: AABBs grow by it and the narrow phase reports points this
    /// far apart. Each pair adds its relative speed times `dt` on top.
    pub margin: Real,
    /// Effects forced on or off; by default each runs when the scene needs it, and resting
    /// islands sleep (`effects.sleep = EffectSwitch::Off` keeps every body awake).
    pub effects: EffectOverrides,
    /// Contact recycling, m: a pair whose bodies turned by less than a degree relative to each
    /// other, and whose contact points slid by less than this (and 1% of the pair's smallest
    /// half extent) since its manifold was computed, keeps that manifold with its depths
    /// updated instead of a fresh separating axis test (`tumble_solver::CachedManifold::
    /// recycle`). 0 computes every manifold every step. The default, 1 mm, is parry3d's
    /// threshold. Every backend recycles by the same rule (the GPU's narrow phase in
    /// `collide_cuboids`; docs/solver.md, "Contact recycling").
    #[cfg_attr(feature = "serde", serde(default = "default_recycle_distance"))]
    pub recycle_distance: Real,
}

#[cfg(feature = "serde")]
fn default_recycle_distance() -> Real {
    tumble_solver::DEFAULT_RECYCLE_DISTANCE
}

impl Default for WorldConfig {
    /// Earth gravity along -y, 60 Hz, the default soft-step solver, CPU.
    fn default() -> Self {
        Self {
            gravity: Vec3::new(0.0, -STANDARD_GRAVITY, 0.0),
            dt: 1.0 / 60.0,
            solver: SolverConfig::default(),
            backend: Backend::Cpu,
            margin: DEFAULT_MARGIN,
            effects: EffectOverrides::default(),
            recycle_distance: tumble_solver::DEFAULT_RECYCLE_DISTANCE,
        }
    }
}

impl WorldConfig {
    /// Checks every field against its range (`tumble_solver::bounds`); the error names the
    /// first bad one, its value and the range.
    pub fn validate(&self) -> Result<(), InvalidParameter> {
        use bounds::*;
        require_length_at_most("gravity", &self.gravity, MAX_GRAVITY, EXPECTED_GRAVITY)?;
        require_in_range("dt", self.dt, MIN_DT, MAX_DT, EXPECTED_DT)?;
        require_in_range("margin", self.margin, 0.0, MAX_MARGIN, EXPECTED_MARGIN)?;
        require_in_range(
            "recycle_distance",
            self.recycle_distance,
            0.0,
            MAX_RECYCLE_DISTANCE,
            EXPECTED_RECYCLE_DISTANCE,
        )?;
        self.solver.validate()
    }
}
