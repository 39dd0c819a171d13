//! Two boxes created half inside each other.

use tumble_geometry::Real;

use super::common::{UNIT_HALF, floor, unit_cube};
use crate::{Scene, SceneCheck};

/// Run length: 3 s, time for a soft contact to push 0.5 m of overlap out and for friction to
/// stop the pair.
const OVERLAP_STEPS: u32 = 180;
/// Allowed final overlap: 1 cm, above the few millimetres of slop solvers keep at rest.
const OVERLAP_MAX_DEPTH: Real = 0.01;
/// Allowed final speed: 0.1 m/s. The separation is driven by a penetration that was 0.5 m;
/// a solver that turns that into velocity at once launches the boxes at metres per second.
const OVERLAP_MAX_SPEED: Real = 0.1;

/// Two unit cubes on the floor whose centres are half a cube apart (0.5 m overlap along x).
pub fn overlap_recovery() -> Scene {
    let mut scene = Scene::new(
        "overlap_recovery",
        "Two unit cubes created half overlapping on the floor; they must separate without \
         exploding.",
    );
    scene.steps = OVERLAP_STEPS;
    scene.bodies.push(floor());
    let offset = 0.5 * UNIT_HALF;
    scene.bodies.push(unit_cube([-offset, UNIT_HALF, 0.0]));
    scene.bodies.push(unit_cube([offset, UNIT_HALF, 0.0]));
    scene.check = SceneCheck::Separates {
        max_depth: OVERLAP_MAX_DEPTH,
        max_speed: OVERLAP_MAX_SPEED,
    };
    scene
}
