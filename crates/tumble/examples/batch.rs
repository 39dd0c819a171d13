//! Sixteen worlds stepped together: a cube pushed along the floor in each, a different push
//! per world, read into one buffer; half the worlds are reset halfway.
//!
//! ```sh
//! cargo run -p tumble --example batch            # on the CPU, one rayon task per world
//! cargo run -p tumble --example batch -- --gpu   # on the GPU, all sixteen in one GPU step
//! ```

use tumble::prelude::*;
use tumble::{Action, POSE_FLOATS, WorldBatch, WorldSpec};

fn main() -> Result<(), Error> {
    let floor = BodyDesc::fixed()
        .cuboid(Vec3::new(20.0, 0.5, 20.0))
        .translation(0.0, -0.5, 0.0);
    let cube = BodyDesc::dynamic().translation(0.0, 0.5, 0.0);
    let backend = if std::env::args().any(|a| a == "--gpu") {
        Backend::Gpu
    } else {
        Backend::Cpu
    };
    let config = WorldConfig {
        backend,
        ..WorldConfig::default()
    };
    let specs: Vec<WorldSpec> = (0..16)
        .map(|_| WorldSpec::new(config).body(floor).body(cube))
        .collect();
    let mut batch = WorldBatch::from_specs(backend, specs)?;
    let ids = batch.ids();
    // Every world has the same bodies: the floor, then the cube.
    let cube = batch.handles(ids[0])?[1];

    // One array of actions for the whole batch: world k's cube slides off at k / 4 m/s.
    let pushes: Vec<Action> = ids
        .iter()
        .enumerate()
        .map(|(k, &id)| {
            Action::set_velocity(
                id,
                cube,
                Vec3::new(k as Real * 0.25, 0.0, 0.0),
                Vec3::zeros(),
            )
        })
        .collect();
    batch.apply_actions(&pushes)?;
    for id in &ids {
        // The state right after the push: what a reset returns to.
        batch.save_state(*id)?;
    }

    let mut poses = vec![0.0; batch.all_poses_len()];
    for step in 0..120 {
        if step == 60 {
            let even: Vec<_> = ids.iter().copied().step_by(2).collect();
            batch.reset(&even)?;
        }
        batch.step()?;
    }
    batch.read_all_poses(&mut poses)?;
    for (k, world) in poses.chunks(2 * POSE_FLOATS).enumerate() {
        let x = world[POSE_FLOATS];
        println!(
            "world {k:2}: cube at x = {x:.3} m after {} steps",
            batch.step_count(ids[k])?
        );
    }
    Ok(())
}

/// `cargo test -p tumble --examples` runs the example as a test.
#[test]
fn example_runs() {
    main().unwrap();
}
