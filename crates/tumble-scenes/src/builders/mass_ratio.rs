//! Heavy bodies on light ones: the case that makes iterative solvers sag.

use tumble_geometry::Real;

use super::common::{UNIT_HALF, floor, unit_cube};
use crate::{Scene, SceneCheck};

/// Density ratio of the top cube to the cubes under it.
pub const HEAVY_DENSITY_RATIO: Real = 100.0;
/// Width ratio of the plank to the cubes under it (its mass ratio is this squared).
pub const WIDE_RATIO: Real = 10.0;
/// Allowed displacement: 5 cm. Under a 100:1 load the column compresses by its contact slop
/// only (millimetres); a solver that cannot carry the ratio lets the load sink through or
/// tips the column far past this.
const MASS_RATIO_SETTLE: Real = 0.05;

/// Three unit cubes of density 1 in a column, with a unit cube 100 times denser on top.
pub fn mass_ratio() -> Scene {
    let mut scene = Scene::new(
        "mass_ratio",
        "A cube 100x denser than the three cubes it rests on; the column must hold still.",
    );
    scene.bodies.push(floor());
    for i in 0..4 {
        let y = UNIT_HALF + i as Real * 2.0 * UNIT_HALF;
        let cube = unit_cube([0.0, y, 0.0]);
        scene.bodies.push(if i == 3 {
            cube.with_density(HEAVY_DENSITY_RATIO)
        } else {
            cube
        });
    }
    scene.check = SceneCheck::StaysPut {
        meters: MASS_RATIO_SETTLE,
    };
    scene
}

/// A plank 10 times wider (and 100 times heavier) than the four unit cubes under its corners.
pub fn wide_on_small() -> Scene {
    let mut scene = Scene::new(
        "wide_on_small",
        "A plank 10x wider than the four unit cubes under its corners; it must hold still.",
    );
    scene.bodies.push(floor());
    let plank_half = WIDE_RATIO * UNIT_HALF;
    let corner = plank_half - UNIT_HALF;
    for (sx, sz) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
        scene
            .bodies
            .push(unit_cube([sx * corner, UNIT_HALF, sz * corner]));
    }
    scene.bodies.push(crate::BodySpec::dynamic(
        [plank_half, UNIT_HALF, plank_half],
        [0.0, 3.0 * UNIT_HALF, 0.0],
    ));
    scene.check = SceneCheck::StaysPut {
        meters: MASS_RATIO_SETTLE,
    };
    scene
}
