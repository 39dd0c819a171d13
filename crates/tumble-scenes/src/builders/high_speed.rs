//! A fast, small box against a thin floor: the tunneling test.

use tumble_geometry::Real;

use crate::{BodySpec, Scene, SceneCheck};

/// Half extent of the falling cube (0.5 m across).
const CUBE_HALF: Real = 0.25;
/// Half thickness of the thin floor (0.2 m thick), top at `y = 0`.
const THIN_FLOOR_HALF: Real = 0.1;
/// Half width of the thin floor.
const THIN_FLOOR_WIDTH: Real = 5.0;
/// Downward speed, m/s: 50 m/s moves 0.83 m per 60 Hz step, more than the floor and cube
/// together (0.7 m), so a discrete step can jump clean over the floor.
const DROP_SPEED: Real = 50.0;
/// Start height of the cube centre: two steps of travel above the floor.
const START_HEIGHT: Real = 1.5;
/// Run length: 1 s.
const HIGH_SPEED_STEPS: u32 = 60;

/// A 0.5 m cube at 50 m/s straight down onto a 0.2 m thick fixed floor.
pub fn high_speed() -> Scene {
    let mut scene = Scene::new(
        "high_speed",
        "A 0.5 m cube at 50 m/s down onto a 0.2 m thick floor; it must not pass through.",
    );
    scene.steps = HIGH_SPEED_STEPS;
    scene.bodies.push(BodySpec::fixed(
        [THIN_FLOOR_WIDTH, THIN_FLOOR_HALF, THIN_FLOOR_WIDTH],
        [0.0, -THIN_FLOOR_HALF, 0.0],
    ));
    scene.bodies.push(
        BodySpec::dynamic([CUBE_HALF; 3], [0.0, START_HEIGHT, 0.0]).with_linear_velocity([
            0.0,
            -DROP_SPEED,
            0.0,
        ]),
    );
    // Below the floor's mid-plane the cube is through: contacts would push it down, not up.
    scene.check = SceneCheck::NoTunneling {
        min_y: -THIN_FLOOR_HALF,
    };
    scene
}
