//! Mass and principal inertia of a solid box of uniform density.

use tumble_geometry::{Cuboid, Real, Vec3};

use crate::InvalidParameter;
use crate::error::require_positive;

/// Mass and the diagonal of the inertia tensor in the box's own (principal) frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Mass in kg.
    pub mass: Real,
    /// Principal moments of inertia about the box's local x, y and z axes, in kg m^2.
    pub principal_inertia: Vec3,
}

impl MassProperties {
    /// A solid box of half extents `h` and `density` (kg/m^3).
    ///
    /// With full sizes `2h`, the moment about x is `m (4hy^2 + 4hz^2) / 12 = m (hy^2 + hz^2) / 3`.
    pub fn cuboid(cuboid: &Cuboid, density: Real) -> Result<Self, InvalidParameter> {
        let h = cuboid.half_extents;
        for (field, v) in [
            ("half_extents.x", h.x),
            ("half_extents.y", h.y),
            ("half_extents.z", h.z),
        ] {
            require_positive(field, v)?;
        }
        require_positive("density", density)?;
        let mass = density * cuboid.volume();
        // A box so small or so light that its mass underflows cannot be simulated.
        require_positive("mass (density * volume)", mass)?;
        let (x2, y2, z2) = (h.x * h.x, h.y * h.y, h.z * h.z);
        let principal_inertia = Vec3::new(y2 + z2, x2 + z2, x2 + y2) * (mass / 3.0);
        if !principal_inertia.iter().all(|i| i.is_finite() && *i > 0.0) {
            return Err(InvalidParameter::new(
                "inertia (from density and half_extents)",
                [
                    principal_inertia.x,
                    principal_inertia.y,
                    principal_inertia.z,
                ],
                "finite moments > 0",
            ));
        }
        Ok(Self {
            mass,
            principal_inertia,
        })
    }

    /// `1 / mass`.
    pub fn inverse_mass(&self) -> Real {
        1.0 / self.mass
    }

    /// The inverse principal moments, component-wise.
    pub fn inverse_principal_inertia(&self) -> Vec3 {
        self.principal_inertia.map(|i| 1.0 / i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_cube_of_unit_density_has_mass_one_and_inertia_one_sixth() {
        // A 1 m cube of 1 kg/m^3: m = 1, I = m (1 + 1) / 12 = 1/6 about every axis.
        let p = MassProperties::cuboid(&Cuboid::new(Vec3::repeat(0.5)), 1.0).unwrap();
        assert!((p.mass - 1.0).abs() < 1e-6);
        for i in p.principal_inertia.iter() {
            assert!((i - 1.0 / 6.0).abs() < 1e-6, "{i}");
        }
    }

    #[test]
    fn box_one_by_two_by_three_matches_the_textbook_formula() {
        // Sizes a, b, c = 1, 2, 3 and density 2: m = 12, Ix = m (b^2 + c^2) / 12 = 13,
        // Iy = m (a^2 + c^2) / 12 = 10, Iz = m (a^2 + b^2) / 12 = 5.
        let p = MassProperties::cuboid(&Cuboid::new(Vec3::new(0.5, 1.0, 1.5)), 2.0).unwrap();
        // f32 carries about 7 digits; 1e-4 relative is far above round-off and far below a
        // wrong formula (a missing factor changes a moment by 2x or more).
        assert!((p.mass - 12.0).abs() < 12.0 * 1e-4);
        let expected = Vec3::new(13.0, 10.0, 5.0);
        for k in 0..3 {
            assert!((p.principal_inertia[k] - expected[k]).abs() < expected[k] * 1e-4);
        }
    }

    #[test]
    fn bad_sizes_and_densities_are_errors_naming_the_field() {
        let cube = Cuboid::new(Vec3::repeat(0.5));
        let e = MassProperties::cuboid(&cube, -1.0).unwrap_err();
        assert_eq!(e.field, "density");
        let e = MassProperties::cuboid(&cube, Real::NAN).unwrap_err();
        assert_eq!(e.field, "density");
        let e = MassProperties::cuboid(&Cuboid::new(Vec3::new(0.5, 0.0, 0.5)), 1.0).unwrap_err();
        assert_eq!(e.field, "half_extents.y");
        let e = MassProperties::cuboid(&Cuboid::new(Vec3::new(0.5, 0.5, Real::INFINITY)), 1.0)
            .unwrap_err();
        assert_eq!(e.field, "half_extents.z");
    }
}
