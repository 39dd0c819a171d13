//! A column far from the origin, where f32 positions are coarse.

use tumble_geometry::Real;

use super::common::{UNIT_HALF, floor_at, unit_cube};
use crate::{Scene, SceneCheck};

/// Boxes in the column.
const FAR_STACK_HEIGHT: usize = 10;
/// Allowed horizontal creep: 2 cm. At 10 km an f32 coordinate is quantized to about 1 mm, so
/// this allows round-off of a few ulps per body but not a column that walks.
const FAR_DRIFT: Real = 0.02;

/// A 10-box column of unit cubes on its own floor, both at `x = offset`.
pub fn far_from_origin(offset: Real) -> Scene {
    let mut scene = Scene::new(
        format!("far_from_origin_{offset}"),
        format!(
            "A {FAR_STACK_HEIGHT}-cube column at x = {offset} m; f32 round-off must not make it creep."
        ),
    );
    scene.bodies.push(floor_at(offset, 0.0));
    for i in 0..FAR_STACK_HEIGHT {
        let y = UNIT_HALF + i as Real * 2.0 * UNIT_HALF;
        scene.bodies.push(unit_cube([offset, y, 0.0]));
    }
    scene.check = SceneCheck::MaxDrift { meters: FAR_DRIFT };
    scene
}
