//! Contact events: a box dropped on a floor begins touching it when it lands, and ends when it
//! is lifted off again.
//!
//! `cargo run -p tumble --example events`

use tumble::ContactEventKind;
use tumble::prelude::*;

fn main() -> Result<(), tumble::Error> {
    let mut world = World::new(WorldConfig::default())?;
    let floor = world.add_body(
        BodyDesc::fixed()
            .cuboid(Vec3::new(5.0, 0.5, 5.0))
            .translation(0.0, -0.5, 0.0),
    )?;
    let cube = world.add_body(BodyDesc::dynamic().translation(0.0, 1.5, 0.0))?;
    world.set_contact_events(true)?;
    let (mut begins, mut ends) = (0, 0);
    for step in 1..=90 {
        if step == 60 {
            // Lift the resting box 2 m and throw it upward.
            world.set_pose(cube, Pose::translation(0.0, 2.5, 0.0))?;
            world.set_linear_velocity(cube, Vec3::new(0.0, 3.0, 0.0))?;
        }
        world.step()?;
        for e in world.contact_events() {
            let other = if e.body_a == floor {
                e.body_b
            } else {
                e.body_a
            };
            match e.kind {
                ContactEventKind::Begin => begins += 1,
                ContactEventKind::End => ends += 1,
            }
            println!(
                "step {step:3} t = {:.3} s: {:?} floor-{other:?}, impulse {:.4} N s at ({:.3}, {:.3}, {:.3})",
                world.time(),
                e.kind,
                e.normal_impulse,
                e.point.x,
                e.point.y,
                e.point.z
            );
        }
        if step == 59 {
            let resting = world.touching_pairs()[0].normal_impulse;
            println!("step {step:3}: resting impulse {resting:.4} N s (m g dt = 0.1635)");
        }
    }
    // One landing, one lift-off (the box is still in the air 30 steps after the throw).
    assert_eq!((begins, ends), (1, 1));
    Ok(())
}

/// `cargo test -p tumble --examples` runs the example as a test.
#[test]
fn example_runs() {
    main().unwrap();
}
