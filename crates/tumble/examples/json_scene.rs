//! A custom scene read from JSON (tumble-scenes' format, as in `crates/tumble-scenes/scenes/`):
//! a floor, a ramp and a box sliding down it.
//!
//! `cargo run -p tumble --example json_scene`

use tumble::prelude::*;
use tumble::scenes::Scene;

/// A floor, and a box on a fixed ramp tilted 30 degrees about z (quaternion `[x, y, z, w]` of
/// a 30 degree turn: `[0, 0, sin 15, cos 15]`), with friction 0.2 below tan 30 = 0.58, so the
/// box slides.
const SCENE: &str = r#"{
  "name": "ramp_slide",
  "description": "A box slides down a 30 degree ramp onto the floor.",
  "steps": 90,
  "bodies": [
    { "kind": "Fixed", "half_extents": [20.0, 0.5, 20.0], "position": [0.0, -0.5, 0.0] },
    { "kind": "Fixed", "half_extents": [3.0, 0.1, 1.0], "position": [0.0, 1.5, 0.0],
      "rotation": [0.0, 0.0, 0.25881904, 0.9659258], "friction": 0.2 },
    { "kind": "Dynamic", "half_extents": [0.25, 0.25, 0.25], "position": [1.5, 2.66, 0.0],
      "rotation": [0.0, 0.0, 0.25881904, 0.9659258], "friction": 0.2 }
  ]
}"#;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let scene = Scene::from_json(SCENE)?;
    let (mut world, handles) = World::from_scene(&scene, WorldConfig::default())?;
    let slider = handles[2];
    let start = world.pose(slider)?.translation.vector;
    for _ in 0..scene.steps {
        world.step()?;
    }
    let end = world.pose(slider)?.translation.vector;
    println!(
        "{}: the box went from ({:.2}, {:.2}) to ({:.2}, {:.2}) in {:.1} s",
        scene.name,
        start.x,
        start.y,
        end.x,
        end.y,
        scene.duration()
    );
    // Friction 0.2 cannot hold a box on a 30 degree slope: it slid down and to the left, a
    // good part of a metre (down the ramp at a = g (sin 30 - 0.2 cos 30) = 3.2 m/s^2).
    assert!(
        end.x < start.x - 0.5 && end.y < start.y - 0.3,
        "the box did not slide: {end:?}"
    );
    Ok(())
}

/// `cargo test -p tumble --examples` runs the example as a test.
#[test]
fn example_runs() {
    main().unwrap();
}
