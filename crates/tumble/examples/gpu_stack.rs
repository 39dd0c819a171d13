//! A stack of ten cubes stepped entirely on the GPU (`Backend::Gpu`). Without a GPU adapter
//! (or built without the `gpu` feature) it says so and exits successfully.
//!
//! `cargo run -p tumble --example gpu_stack`

use tumble::prelude::*;

const LAYERS: usize = 10;

fn main() -> Result<(), tumble::Error> {
    let config = WorldConfig {
        backend: Backend::Gpu,
        ..Default::default()
    };
    let mut world = match World::new(config) {
        Ok(world) => world,
        Err(e @ tumble::Error::BackendUnavailable { .. }) => {
            println!("no GPU backend here, nothing to run: {e}");
            return Ok(());
        }
        Err(e) => return Err(e),
    };
    world.add_body(
        BodyDesc::fixed()
            .cuboid(Vec3::new(10.0, 0.5, 10.0))
            .translation(0.0, -0.5, 0.0),
    )?;
    let cubes: Vec<BodyHandle> = (0..LAYERS)
        .map(|i| world.add_body(BodyDesc::dynamic().translation(0.0, 0.5 + i as Real, 0.0)))
        .collect::<Result<_, _>>()?;
    for _ in 0..60 {
        world.step()?;
    }
    let top = world.pose(cubes[LAYERS - 1])?.translation.vector;
    println!(
        "after 1 s on the GPU the top of {LAYERS} cubes is at ({:.3}, {:.3}, {:.3}) m",
        top.x, top.y, top.z
    );
    // The stack stands: the top cube's centre stays within 5 cm of where it started (9.5 m),
    // far less than the metre a collapse would take it.
    let expected = LAYERS as Real - 0.5;
    assert!(
        (top.y - expected).abs() < 0.05 && top.x.abs() < 0.05 && top.z.abs() < 0.05,
        "the stack moved: {top:?}"
    );
    Ok(())
}

/// `cargo test -p tumble --examples` runs the example as a test.
#[test]
fn example_runs() {
    main().unwrap();
}
