//! The README's example: a unit cube dropped from 2 m comes to rest on a fixed floor.
//!
//! `cargo run -p tumble --example hello_cube`

use tumble::prelude::*;

fn main() -> Result<(), tumble::Error> {
    // Backend::Gpu runs the whole step on the GPU; Backend::Hybrid runs collision there and
    // the solver here. Both return Err when no adapter exists.
    let mut world = World::new(WorldConfig {
        backend: Backend::Cpu,
        ..Default::default()
    })?;
    world.add_body(
        BodyDesc::fixed()
            .cuboid(Vec3::new(50.0, 0.5, 50.0))
            .translation(0.0, -0.5, 0.0),
    )?;
    let cube = world.add_body(
        BodyDesc::dynamic()
            .cuboid(Vec3::new(0.5, 0.5, 0.5))
            .translation(0.0, 2.0, 0.0)
            .density(1.0)
            .friction(0.6),
    )?;
    for _ in 0..120 {
        world.step()?;
    }
    let y = world.pose(cube)?.translation.vector.y;
    println!("the cube rests with its centre at y = {y:.4} m");
    // Resting on the floor's top face (y = 0), the unit cube's centre is half a metre up; a
    // centimetre covers the contact's slop.
    assert!((y - 0.5).abs() < 0.01, "the cube is not resting: y = {y}");
    Ok(())
}

/// `cargo test -p tumble --examples` runs the example as a test.
#[test]
fn example_runs() {
    main().unwrap();
}
