//! Surface materials and how two of them combine at a contact.

use tumble_geometry::Real;

use crate::InvalidParameter;
use crate::error::require_non_negative;

/// Friction and restitution of a body's surface.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Material {
    /// Coulomb friction coefficient (>= 0).
    pub friction: Real,
    /// Coefficient of restitution (0 = no bounce, 1 = elastic).
    pub restitution: Real,
}

/// The default friction coefficient: a common middle value for dry contacts (wood on wood).
pub const DEFAULT_FRICTION: Real = 0.6;

impl Default for Material {
    fn default() -> Self {
        Self {
            friction: DEFAULT_FRICTION,
            restitution: 0.0,
        }
    }
}

impl Material {
    /// Checks both coefficients: finite, friction >= 0, restitution in `[0, 1]`.
    pub fn validate(&self) -> Result<(), InvalidParameter> {
        require_non_negative("friction", self.friction)?;
        if !(self.restitution.is_finite() && (0.0..=1.0).contains(&self.restitution)) {
            return Err(InvalidParameter::new(
                "restitution",
                self.restitution,
                "a number in [0, 1]",
            ));
        }
        Ok(())
    }
}

/// The friction of a contact: the geometric mean `sqrt(mu_a * mu_b)`.
///
/// Box2D uses the same rule (`b2MixFriction`): a frictionless surface makes the contact
/// frictionless, and equal coefficients combine to themselves, so a scene giving both the box
/// and the ramp `mu` gets exactly `mu`.
pub fn mix_friction(a: Real, b: Real) -> Real {
    (a * b).sqrt()
}

/// The restitution of a contact: the larger of the two (Box2D's `b2MixRestitution`), so one
/// bouncy body bounces on any floor.
pub fn mix_restitution(a: Real, b: Real) -> Real {
    a.max(b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_frictions_combine_to_themselves_and_zero_wins() {
        assert!((mix_friction(0.5, 0.5) - 0.5).abs() < 1e-7);
        assert_eq!(mix_friction(0.0, 0.9), 0.0);
        assert_eq!(mix_restitution(0.2, 0.7), 0.7);
    }

    #[test]
    fn unequal_frictions_combine_to_their_geometric_mean() {
        // sqrt(0.2 * 0.8) = 0.4 and sqrt(0.1 * 0.9) = 0.3. The other common rules give values
        // far outside one f32 epsilon of these: min 0.2 and 0.1, harmonic mean 2ab / (a + b)
        // 0.32 and 0.18, arithmetic mean 0.5 and 0.5, max 0.8 and 0.9.
        for (a, b, mixed) in [(0.2, 0.8, 0.4), (0.1, 0.9, 0.3)] {
            for (x, y) in [(a, b), (b, a)] {
                let mu = mix_friction(x, y);
                assert!(
                    (mu - mixed).abs() <= Real::EPSILON,
                    "mix_friction({x}, {y}) = {mu}, expected sqrt({x} * {y}) = {mixed}"
                );
            }
        }
    }

    #[test]
    fn out_of_range_materials_are_rejected_by_name() {
        let bad = Material {
            friction: -0.1,
            restitution: 0.0,
        };
        assert_eq!(bad.validate().unwrap_err().field, "friction");
        let bad = Material {
            friction: 0.5,
            restitution: 1.5,
        };
        assert_eq!(bad.validate().unwrap_err().field, "restitution");
    }
}
