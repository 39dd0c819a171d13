//! Soft constraint coefficients: a contact as a damped spring solved implicitly.
//!
//! From Catto, "Solver2D" (2024) and Box2D v3's `b2MakeSoft`: with `omega = 2 pi hertz`,
//! `zeta` the damping ratio and `h` the substep, the implicit spring-damper gives
//! `bias_rate = omega / (2 zeta + h omega)`, `mass_scale = h omega (2 zeta + h omega) /
//! (1 + h omega (2 zeta + h omega))` and `impulse_scale = 1 / (1 + h omega (2 zeta + h omega))`.
//! The impulse update is then `-m_eff (mass_scale vn + mass_scale bias_rate s) -
//! impulse_scale lambda`.

use tumble_geometry::Real;

/// The three coefficients of a soft constraint for one substep length.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Softness {
    /// Converts separation (m) into a velocity bias (1/s).
    pub bias_rate: Real,
    /// Scales the effective mass (1 = rigid).
    pub mass_scale: Real,
    /// Fraction of the accumulated impulse removed per pass (0 = rigid).
    pub impulse_scale: Real,
}

impl Softness {
    /// A rigid constraint: no bias, full mass, no impulse leak.
    pub const RIGID: Self = Self {
        bias_rate: 0.0,
        mass_scale: 1.0,
        impulse_scale: 0.0,
    };

    /// The coefficients of a spring of `hertz` and damping ratio `zeta` solved with substep `h`.
    pub fn new(hertz: Real, zeta: Real, h: Real) -> Self {
        if hertz == 0.0 {
            return Self::RIGID;
        }
        let omega = 2.0 * std::f32::consts::PI * hertz;
        let a1 = 2.0 * zeta + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        Self {
            bias_rate: omega / a1,
            mass_scale: a2 * a3,
            impulse_scale: a3,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stiffer_springs_are_closer_to_rigid() {
        let h = 1.0 / 240.0;
        let soft = Softness::new(30.0, 10.0, h);
        let stiff = Softness::new(3000.0, 10.0, h);
        // mass_scale + impulse_scale = 1 by construction (a2 a3 + a3 = 1).
        assert!((soft.mass_scale + soft.impulse_scale - 1.0).abs() < 1e-6);
        assert!(stiff.mass_scale > soft.mass_scale);
        assert!(stiff.impulse_scale < soft.impulse_scale);
        assert!(soft.bias_rate > 0.0);
    }
}
