//! The speculative margin of a pair: how far apart two boxes may be and still get a manifold,
//! so that a pair that can close within the step is caught before it overlaps.

use tumble_geometry::{Real, Vec3};

/// What the margin needs of one box: its size and its velocities at the start of the step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BoxMotion {
    /// Half extents, m (their norm is the radius a corner turns on).
    pub half_extents: Vec3,
    /// Linear velocity, m/s.
    pub linear: Vec3,
    /// Angular velocity, rad/s.
    pub angular: Vec3,
}

/// The speculative margin of a pair: the base `margin` plus how far the two boxes can close in
/// one step (relative speed of the centres plus the rim speed of each spin, times `dt`).
#[inline]
pub fn pair_margin(a: &BoxMotion, b: &BoxMotion, margin: Real, dt: Real) -> Real {
    let closing = (b.linear - a.linear).norm()
        + a.angular.norm() * a.half_extents.norm()
        + b.angular.norm() * b.half_extents.norm();
    margin + closing * dt
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn still_boxes_keep_the_base_margin() {
        let a = BoxMotion {
            half_extents: Vec3::repeat(0.5),
            ..Default::default()
        };
        assert_eq!(pair_margin(&a, &a, 0.02, 1.0 / 60.0), 0.02);
    }

    #[test]
    fn closing_speed_and_both_spins_add_up() {
        // Relative speed (3, 4, 0): 5 m/s. A spins at 2 rad/s with radius 5 (half extents
        // (0, 3, 4)): 10 m/s at the rim. B spins at 1 rad/s with radius 13 (5, 12, 0): 13 m/s.
        let a = BoxMotion {
            half_extents: Vec3::new(0.0, 3.0, 4.0),
            linear: Vec3::new(1.0, 0.0, 0.0),
            angular: Vec3::new(0.0, 0.0, 2.0),
        };
        let b = BoxMotion {
            half_extents: Vec3::new(5.0, 12.0, 0.0),
            linear: Vec3::new(4.0, 4.0, 0.0),
            angular: Vec3::new(1.0, 0.0, 0.0),
        };
        assert_eq!(pair_margin(&a, &b, 0.5, 0.25), 0.5 + 28.0 * 0.25);
        // Symmetric in the two boxes.
        assert_eq!(pair_margin(&b, &a, 0.5, 0.25), 7.5);
    }
}
