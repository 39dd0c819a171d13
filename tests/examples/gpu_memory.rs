//! GPU memory per body of a `Backend::Gpu` world, buffer by buffer, after a few steps:
//!
//! `XDG_RUNTIME_DIR=/tmp TUMBLE_REQUIRE_GPU=1 cargo run --release -p tumble-tests --example gpu_memory -- [scene ...] [steps=N]`
//!
//! Scenes: `pyramidH` (packed, tumble-scenes' builder), `poolN` (N unit cubes dropped into a
//! walled pool, `tumble_scenes::builders::pool`), `stackN`, or a scene file `NAME.json` (such
//! as those `cargo xtask bench-gpu --write-scenes DIR` writes) (default: pyramid24
//! pool10000), steps 3. Prints each buffer (its pool, name, bytes and bytes per body, largest first) and
//! the total per body; docs/gpu.md ("Memory per body") has the figures.

use tumble::prelude::*;
use tumble::scenes::{self, Scene};

fn scene(name: &str) -> Scene {
    let number = |prefix: &str| -> usize {
        name[prefix.len()..]
            .parse()
            .unwrap_or_else(|_| panic!("scene {name:?}: expected a number after {prefix:?}"))
    };
    if name.ends_with(".json") {
        let text = std::fs::read_to_string(name)
            .unwrap_or_else(|e| panic!("reading the scene file {name}: {e}"));
        Scene::from_json(&text).unwrap_or_else(|e| panic!("the scene file {name}: {e}"))
    } else if name.starts_with("pyramid") {
        scenes::pyramid(number("pyramid"))
    } else if name.starts_with("pool") {
        scenes::pool(number("pool"))
    } else if name.starts_with("stack") {
        scenes::stack(number("stack"))
    } else {
        panic!("unknown scene {name:?}: pyramidH, poolN or stackN")
    }
}

fn main() {
    let mut steps = 3usize;
    let mut names = Vec::new();
    for arg in std::env::args().skip(1) {
        match arg.strip_prefix("steps=") {
            Some(n) => steps = n.parse().expect("steps=N"),
            None => names.push(arg),
        }
    }
    if names.is_empty() {
        names = vec!["pyramid24".into(), "pool10000".into()];
    }
    for name in &names {
        let scene = scene(name);
        let config = WorldConfig {
            backend: Backend::Gpu,
            ..Default::default()
        };
        let (mut world, _) = World::from_scene(&scene, config).expect("the scene builds");
        for _ in 0..steps {
            world.step().expect("the step runs");
        }
        let bodies = scene.bodies.len() as f64;
        let mut sizes = world.device_buffer_sizes();
        sizes.sort_by(|a, b| b.2.cmp(&a.2).then(a.0.cmp(b.0)).then(a.1.cmp(b.1)));
        let total: u64 = sizes.iter().map(|s| s.2).sum();
        println!(
            "\n{name}: {} bodies, {} contacts after {steps} steps; {total} bytes, {:.1} per body",
            scene.bodies.len(),
            world.contacts().len(),
            total as f64 / bodies
        );
        println!("| pool | buffer | bytes | bytes per body |");
        println!("|---|---|---:|---:|");
        for (pool, buffer, bytes) in sizes {
            if bytes as f64 / bodies >= 1.0 {
                println!(
                    "| {pool} | {buffer} | {bytes} | {:.1} |",
                    bytes as f64 / bodies
                );
            }
        }
    }
}
