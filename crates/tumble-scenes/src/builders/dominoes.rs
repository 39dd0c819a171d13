//! A row of dominoes, the first one pushed.

use tumble_geometry::{Real, Vec3};

use super::common::floor;
use crate::{BodySpec, Scene, SceneCheck};

/// Domino half extents: 0.2 m thick (x), 2 m tall (y), 1 m wide (z).
const DOMINO_HALF: [Real; 3] = [0.1, 1.0, 0.5];
/// Centre-to-centre spacing along x: half the height, so a falling domino strikes the next
/// when tilted by about 24 degrees, well before it lies flat.
const DOMINO_SPACING: Real = 1.0;
/// The push, rad/s about -z (tipping toward +x), applied as a rotation about the domino's
/// front bottom edge. Tipping over that edge needs about 0.3 rad/s (the centre must rise
/// by sqrt(1 + 0.1^2) - 1 = 5 mm); 1.5 rad/s starts the chain at once yet gently.
const PUSH_RATE: Real = 1.5;
/// Final tilt every domino must reach: 45 degrees. The chain's dominoes end leaning on their
/// neighbours at 70 degrees or more; one still standing reads zero.
const MIN_TILT_DEG: Real = 45.0;
/// Base run length in steps (4 s), plus `STEPS_PER_DOMINO` per domino (0.5 s each: a domino
/// of this size takes about 0.3 s from the strike to the next strike).
const BASE_STEPS: u32 = 240;
/// Extra steps per domino, see `BASE_STEPS`.
const STEPS_PER_DOMINO: u32 = 30;

/// `n` dominoes in a row along +x; the first is tipped toward the others.
pub fn dominoes(n: usize) -> Scene {
    let mut scene = Scene::new(
        format!("dominoes_{n}"),
        format!("A row of {n} dominoes, the first pushed; every one must fall."),
    );
    scene.steps = BASE_STEPS + STEPS_PER_DOMINO * n as u32;
    scene.bodies.push(floor());
    for i in 0..n {
        let centre = [i as Real * DOMINO_SPACING, DOMINO_HALF[1], 0.0];
        let mut domino = BodySpec::dynamic(DOMINO_HALF, centre);
        if i == 0 {
            // Rigid rotation about the front bottom edge: v = w x (centre - pivot).
            let w = Vec3::new(0.0, 0.0, -PUSH_RATE);
            let r = Vec3::new(-DOMINO_HALF[0], DOMINO_HALF[1], 0.0);
            domino = domino
                .with_angular_velocity(w.into())
                .with_linear_velocity(w.cross(&r).into());
        }
        scene.bodies.push(domino);
    }
    scene.check = SceneCheck::Topples {
        min_tilt_deg: MIN_TILT_DEG,
    };
    scene
}
