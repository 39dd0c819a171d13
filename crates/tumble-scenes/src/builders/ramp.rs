//! A box on a tilted fixed ramp: Coulomb friction against its closed-form answer.

use tumble_geometry::{Real, Rot, Vec3};

use super::common::UNIT_HALF;
use crate::scene::STANDARD_GRAVITY;
use crate::{BodySpec, Scene, SceneCheck};

/// Ramp half extents: 20 m long (along its local x), 1 m thick, 4 m wide.
const RAMP_HALF: [Real; 3] = [10.0, 0.5, 2.0];
/// Where the box starts along the ramp, from its centre, in meters: on the upper half, so a
/// slide at full gravity (about 10 m in 2 s at 45 degrees) would still end on the ramp.
const BOX_START: Real = 5.0;
/// Run length: 2 s at 60 Hz.
const RAMP_STEPS: u32 = 120;
/// Allowed error of the measured acceleration: 0.1 m/s^2, 1% of g, well under the change
/// a 0.01 error in the friction coefficient makes (g cos a * 0.01 is about 0.085 at 30 degrees).
const RAMP_TOLERANCE: Real = 0.1;

/// Coulomb's prediction for a box released on a slope of `angle_deg` with friction `mu`:
/// `g (sin a - mu cos a)` down the slope when positive, zero when static friction holds.
pub fn ramp_acceleration(angle_deg: Real, mu: Real) -> Real {
    let a = angle_deg.to_radians();
    (STANDARD_GRAVITY * (a.sin() - mu * a.cos())).max(0.0)
}

/// A unit cube at rest on a fixed ramp tilted `angle_deg` about z (rising toward +x), both
/// with friction `mu`, so the combined coefficient is `mu` under any combine rule.
pub fn friction_ramp(angle_deg: Real, mu: Real) -> Scene {
    let expected = ramp_acceleration(angle_deg, mu);
    let verdict = if expected > 0.0 { "slide" } else { "stick" };
    let mut scene = Scene::new(
        format!("friction_ramp_{angle_deg}deg_mu{mu}"),
        format!(
            "A cube on a {angle_deg} degree ramp with friction {mu}; it must {verdict} \
             (Coulomb: {expected:.3} m/s^2)."
        ),
    );
    scene.steps = RAMP_STEPS;
    let angle = angle_deg.to_radians();
    let rot = Rot::from_axis_angle(&Vec3::z_axis(), angle);
    let q = [rot.i, rot.j, rot.k, rot.w];
    scene.bodies.push(
        BodySpec::fixed(RAMP_HALF, [0.0; 3])
            .with_rotation(q)
            .with_friction(mu),
    );
    let local = Vec3::new(BOX_START, RAMP_HALF[1] + UNIT_HALF, 0.0);
    let centre = rot * local;
    scene.bodies.push(
        BodySpec::dynamic([UNIT_HALF; 3], centre.into())
            .with_rotation(q)
            .with_friction(mu),
    );
    let down = rot * Vec3::new(-1.0, 0.0, 0.0);
    scene.check = SceneCheck::Slides {
        direction: down.into(),
        expected_acceleration: expected,
        tolerance: RAMP_TOLERANCE,
    };
    scene
}
