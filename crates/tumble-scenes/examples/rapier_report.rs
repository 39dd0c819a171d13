//! Runs every canonical scene (or those whose name contains the first argument) in rapier3d
//! for its default number of steps and prints each scene's check verdict: a reference for
//! what a mature solver achieves on the scenes' criteria.
//!
//! `cargo run --release -p tumble-scenes --features rapier --example rapier_report [filter]
//! [solver_iterations]`

use std::time::Instant;

use tumble_scenes::{CheckTracker, RapierOptions, build_rapier_with, canonical};

fn main() {
    let filter = std::env::args().nth(1).unwrap_or_default();
    let mut options = RapierOptions::default();
    if let Some(n) = std::env::args().nth(2) {
        options.solver_iterations = n.parse().expect("solver_iterations must be an integer");
    }
    for scene in canonical().iter().filter(|s| s.name.contains(&filter)) {
        let mut world = build_rapier_with(scene, &options);
        let mut tracker = CheckTracker::new(scene);
        let start = Instant::now();
        for _ in 0..scene.steps {
            world.step();
            let states = world.body_states();
            tracker.observe(&states).expect("one state per scene body");
        }
        println!(
            "{} ({} bodies, {} steps, {:.2} s): {}",
            scene.name,
            scene.bodies.len(),
            scene.steps,
            start.elapsed().as_secs_f64(),
            tracker.finish()
        );
    }
}
