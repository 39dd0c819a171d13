//! Resting structures of unit cubes and bricks: the column, the pyramid, the wall.

use tumble_geometry::Real;

use super::common::{LAYER_GAP, UNIT_HALF, floor, unit_cube};
use crate::{BodySpec, Scene, SceneCheck};

/// Horizontal creep allowed for a column: a 20-box stack must stand for 10 s within 1 cm.
const STACK_DRIFT: Real = 0.01;
/// Horizontal creep allowed for a pyramid: 5 cm, a twentieth of a cube; a pyramid that fails
/// slides whole cubes, far past this.
const PYRAMID_DRIFT: Real = 0.05;
/// Horizontal creep allowed for a wall: 2 cm.
const WALL_DRIFT: Real = 0.02;
/// Brick half extents: 1 m long (x), 0.5 m tall and deep, the classic 2:1 brick.
const BRICK_HALF: [Real; 3] = [0.5, 0.25, 0.25];

/// A column of `n` unit cubes standing on the floor, each exactly resting on the one below.
pub fn stack(n: usize) -> Scene {
    let mut scene = Scene::new(
        format!("stack_{n}"),
        format!("A column of {n} unit cubes resting on the floor; it must not creep or topple."),
    );
    scene.bodies.push(floor());
    for i in 0..n {
        let y = UNIT_HALF + i as Real * 2.0 * UNIT_HALF;
        scene.bodies.push(unit_cube([0.0, y, 0.0]));
    }
    scene.check = SceneCheck::MaxDrift {
        meters: STACK_DRIFT,
    };
    scene
}

/// Number of cubes in `pyramid(h)`: the sum of `k^2` for `k = 1..=h`.
pub fn pyramid_cube_count(h: usize) -> usize {
    h * (h + 1) * (2 * h + 1) / 6
}

/// A square pyramid of `h` layers: layer `k` from the top is a `k x k` square of unit cubes,
/// each cube resting on the four below it (centred over their shared corner), with a
/// `LAYER_GAP` between neighbours of a layer and exact contact between layers.
pub fn pyramid(h: usize) -> Scene {
    let mut scene = Scene::new(
        format!("pyramid_{h}"),
        format!(
            "A {h}-layer square pyramid of {} unit cubes; it must stand without creeping.",
            pyramid_cube_count(h)
        ),
    );
    scene.bodies.push(floor());
    let pitch = 2.0 * UNIT_HALF + LAYER_GAP;
    for level in 0..h {
        // `level` 0 is the bottom layer, an h x h square.
        let k = h - level;
        let y = UNIT_HALF + level as Real * 2.0 * UNIT_HALF;
        let first = -(k as Real - 1.0) * 0.5 * pitch;
        for i in 0..k {
            for j in 0..k {
                let x = first + i as Real * pitch;
                let z = first + j as Real * pitch;
                scene.bodies.push(unit_cube([x, y, z]));
            }
        }
    }
    scene.check = SceneCheck::MaxDrift {
        meters: PYRAMID_DRIFT,
    };
    scene
}

/// A running-bond brick wall `w` bricks long and `h` rows high, in the x-y plane: even rows
/// hold `w` bricks, odd rows `w - 1` bricks shifted by half a brick, so every joint is
/// bridged by the brick above.
pub fn wall(w: usize, h: usize) -> Scene {
    let mut scene = Scene::new(
        format!("wall_{w}x{h}"),
        format!("A running-bond wall of {w} x {h} bricks; it must stand without creeping."),
    );
    scene.bodies.push(floor());
    let pitch = 2.0 * BRICK_HALF[0] + LAYER_GAP;
    for row in 0..h {
        let count = if row.is_multiple_of(2) {
            w
        } else {
            w.saturating_sub(1)
        };
        let y = BRICK_HALF[1] + row as Real * 2.0 * BRICK_HALF[1];
        let first = -(count as Real - 1.0) * 0.5 * pitch;
        for i in 0..count {
            let x = first + i as Real * pitch;
            scene
                .bodies
                .push(BodySpec::dynamic(BRICK_HALF, [x, y, 0.0]));
        }
    }
    scene.check = SceneCheck::MaxDrift { meters: WALL_DRIFT };
    scene
}
