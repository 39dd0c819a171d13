//! Spatial queries: rays cast straight down onto a floor with a cube on it, the nearest hit
//! and every hit along a ray.
//!
//! `cargo run -p tumble --example ray_casts`

use tumble::QueryFilter;
use tumble::prelude::*;

fn main() -> Result<(), tumble::Error> {
    let mut world = World::new(WorldConfig::default())?;
    let floor = world.add_body(
        BodyDesc::fixed()
            .cuboid(Vec3::new(5.0, 0.5, 5.0))
            .translation(0.0, -0.5, 0.0),
    )?;
    let cube = world.add_body(BodyDesc::dynamic().translation(0.0, 0.5, 0.0))?;
    for _ in 0..10 {
        world.step()?;
    }
    let down = -Vec3::y();
    for x in [-1.0, 0.0, 0.25] {
        let origin = Point3::new(x, 5.0, 0.0);
        let hit = world.cast_ray(origin, down, 10.0, QueryFilter::default())?;
        match hit {
            Some(h) => {
                let what = if h.body == cube { "cube" } else { "floor" };
                println!(
                    "ray down at x = {x:5.2}: {what} at y = {:.3} (normal {:?})",
                    h.point.y,
                    h.normal.as_slice()
                );
            }
            None => println!("ray down at x = {x:5.2}: nothing"),
        }
    }
    // The ray through the cube's centre: its nearest hit, then every hit along it.
    let above = Point3::new(0.0, 5.0, 0.0);
    let center = world.cast_ray(above, down, 10.0, QueryFilter::default())?;
    let center = center.expect("the cube is under the ray");
    // The cube rests on the floor: its top face at 1 m, within the contact's slop.
    assert_eq!(center.body, cube);
    assert!((center.point.y - 1.0).abs() < 0.01, "{center:?}");
    let all = world.cast_ray_all(above, down, 10.0, QueryFilter::default())?;
    println!(
        "every hit straight down through the cube: {} bodies",
        all.len()
    );
    // Through the cube into the floor: both, nearest first.
    assert_eq!(
        all.iter().map(|h| h.body).collect::<Vec<_>>(),
        [cube, floor]
    );
    Ok(())
}

/// `cargo test -p tumble --examples` runs the example as a test.
#[test]
fn example_runs() {
    main().unwrap();
}
