//! Many boxes dropped into a walled container.

use tumble_geometry::Real;

use super::common::UNIT_HALF;
use crate::{BodySpec, Scene, SceneCheck};

/// Spacing of the drop grid, in meters. A unit cube in any orientation fits in a sphere of
/// radius `sqrt(3) / 2 = 0.866`, so 1.8 m keeps every pair of rotated cubes apart at the start.
const DROP_PITCH: Real = 1.8;
/// Height of the lowest drop layer's centres above the floor, in meters.
const DROP_HEIGHT: Real = 1.5;
/// Clearance between the drop grid and the inner wall faces, in meters.
const WALL_CLEARANCE: Real = 0.5;
/// Wall and floor thickness, in meters.
const WALL_THICKNESS: Real = 1.0;
/// How far the walls rise above the highest drop layer, in meters: nothing dropped can leave
/// over the top without gaining energy.
const WALL_HEADROOM: Real = 1.0;
/// Golden-ratio conjugate: its multiples modulo 1 spread evenly over [0, 1), giving every box
/// a different, reproducible orientation without a random number generator.
const GOLDEN: Real = 0.618_034;

/// `n` unit cubes, each in its own orientation, dropped in a roughly cubic grid into a square
/// container (floor plus four walls) just wide enough for the grid.
pub fn pool(n: usize) -> Scene {
    let mut scene = Scene::new(
        format!("pool_{n}"),
        format!("{n} unit cubes dropped into a walled container; they must pile up inside it."),
    );
    // A g x g grid per layer with g the cube root: the drop column is about as tall as wide.
    let g = ((n as f64).cbrt().ceil() as usize).max(1);
    let layers = n.div_ceil(g * g);
    let inner_half = 0.5 * g as Real * DROP_PITCH + WALL_CLEARANCE;
    let top = DROP_HEIGHT + layers as Real * DROP_PITCH;
    let wall_height = top + WALL_HEADROOM;
    let t = 0.5 * WALL_THICKNESS;
    let outer = inner_half + WALL_THICKNESS;

    scene
        .bodies
        .push(BodySpec::fixed([outer, t, outer], [0.0, -t, 0.0]));
    let wall_y = 0.5 * wall_height;
    for sign in [-1.0, 1.0] {
        let x = sign * (inner_half + t);
        scene
            .bodies
            .push(BodySpec::fixed([t, wall_y, outer], [x, wall_y, 0.0]));
        scene
            .bodies
            .push(BodySpec::fixed([outer, wall_y, t], [0.0, wall_y, x]));
    }

    let first = -(g as Real - 1.0) * 0.5 * DROP_PITCH;
    for i in 0..n {
        let layer = i / (g * g);
        let row = (i / g) % g;
        let col = i % g;
        let position = [
            first + col as Real * DROP_PITCH,
            DROP_HEIGHT + layer as Real * DROP_PITCH,
            first + row as Real * DROP_PITCH,
        ];
        let phase = (i as Real * GOLDEN).fract();
        let axis = [1.0, phase, 1.0 - phase];
        let angle = phase * std::f32::consts::PI;
        scene
            .bodies
            .push(BodySpec::dynamic([UNIT_HALF; 3], position).with_axis_angle(axis, angle));
    }
    scene.check = SceneCheck::Contained {
        min: [-inner_half, 0.0, -inner_half],
        max: [inner_half, wall_height, inner_half],
    };
    scene
}
