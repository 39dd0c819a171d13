//! A free box spinning in zero gravity: the gyroscopic test.

use tumble_geometry::Real;

use crate::{BodySpec, Scene, SceneCheck};

/// Half extents of the 1 x 2 x 3 m box. Its principal moments are proportional to
/// `2^2 + 3^2 = 13` (x, the major axis), `1 + 9 = 10` (y, intermediate) and `1 + 4 = 5` (z).
const SPIN_HALF: [Real; 3] = [0.5, 1.0, 1.5];
/// Initial angular velocity, rad/s, world = body axes at the start. Mostly about the major
/// axis x, where the spin is stable, with 1 rad/s about each minor axis, so the body nutates
/// and its angular velocity wanders while the angular momentum must stay fixed. A spin mostly
/// about y (the intermediate axis) would flip over (the Dzhanibekov effect), a harder and
/// chaotic case kept out of the canonical set.
const SPIN: [Real; 3] = [6.0, 1.0, 1.0];
/// Allowed relative change of the angular momentum over the run: 1%. An integrator that
/// drops the gyroscopic term keeps the angular velocity instead, and with 1 rad/s off-axis
/// its momentum swings by more than 10% within one nutation.
const SPIN_REL_TOL: Real = 0.01;

/// A 1 x 2 x 3 m box spinning freely about its major axis with a wobble, no gravity.
pub fn spinning_box() -> Scene {
    let mut scene = Scene::new(
        "spinning_box",
        "A 1x2x3 m box spinning mostly about its major axis in zero gravity; its angular \
         momentum must be conserved.",
    );
    scene.gravity = [0.0; 3];
    scene
        .bodies
        .push(BodySpec::dynamic(SPIN_HALF, [0.0; 3]).with_angular_velocity(SPIN));
    scene.check = SceneCheck::AngularMomentum {
        rel_tol: SPIN_REL_TOL,
    };
    scene
}
