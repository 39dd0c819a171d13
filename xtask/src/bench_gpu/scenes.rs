//! The scenes of `bench-gpu`: the named set, the generated box pool, the JSON files for the
//! peer script, and the drift and lowest body read at the end of a run.

use super::*;

/// The scenes of a default run, in order.
pub(super) const DEFAULT_SCENES: &[&str] = &[
    "stack20",
    "pyramid24",
    "pyramid50",
    "pyramid100",
    "nexus_pyramid50",
    "pool1000000",
];
/// The scenes of `--quick`: small enough for a software rasterizer in a few minutes.
pub(super) const QUICK_SCENES: &[&str] = &["stack20", "pyramid8", "pool10000"];
/// Layers of the generated box pool: columns of this many unit cubes resting on the floor.
pub(super) const POOL_LAYERS: usize = 16;
/// Horizontal gap between neighbouring columns of the pool, as between the cubes of a
/// pyramid's layer (`tumble_scenes::builders::common::LAYER_GAP`).
pub(super) const POOL_GAP: f32 = builders::common::LAYER_GAP;

/// A scene of the benchmark, or why it cannot be built.
pub(super) fn scene_named(name: &str) -> Result<Scene, String> {
    let number = |rest: &str| {
        rest.replace('_', "")
            .parse::<usize>()
            .map_err(|_| format!("scene {name:?}: expected a number after the kind"))
    };
    if let Some(h) = name.strip_prefix("nexus_pyramid") {
        number(h)?;
        return Err(format!(
            "no builder for nexus's spaced dropped pyramid in tumble-scenes; {name} is skipped"
        ));
    }
    if let Some(n) = name.strip_prefix("stack") {
        return Ok(builders::stack(number(n)?));
    }
    if let Some(h) = name.strip_prefix("pyramid") {
        return Ok(builders::pyramid(number(h)?));
    }
    if let Some(n) = name.strip_prefix("pool") {
        return Ok(box_pool(number(n)?));
    }
    Err(format!(
        "unknown scene {name:?}: stackN, pyramidH, poolN or nexus_pyramidH"
    ))
}

/// `n` unit cubes at rest on a fixed floor, in square columns of [`POOL_LAYERS`] cubes (the top
/// layer partly filled), neighbouring columns [`POOL_GAP`] apart and each cube exactly on the
/// one below: every cube is in contact from the first step.
pub fn box_pool(n: usize) -> Scene {
    let per_layer = n.div_ceil(POOL_LAYERS).max(1);
    let side = (per_layer as f64).sqrt().ceil() as usize;
    let half = builders::common::UNIT_HALF;
    let pitch = 2.0 * half + POOL_GAP;
    let floor_half = 0.5 * side as f32 * pitch + 2.0;
    let mut scene = Scene::new(
        format!("pool_{n}"),
        format!(
            "{n} unit cubes at rest in columns of {POOL_LAYERS} on a floor, {side} x {side} columns."
        ),
    );
    scene.bodies.push(BodySpec::fixed(
        [floor_half, 0.5, floor_half],
        [0.0, -0.5, 0.0],
    ));
    let first = -(side as f32 - 1.0) * 0.5 * pitch;
    for i in 0..n {
        let layer = i / (side * side);
        let row = (i / side) % side;
        let col = i % side;
        scene.bodies.push(builders::common::unit_cube([
            first + col as f32 * pitch,
            half + layer as f32 * 2.0 * half,
            first + row as f32 * pitch,
        ]));
    }
    scene
}

/// The scene's up axis: against gravity (y when there is none).
pub(super) fn up_axis(scene: &Scene) -> [f32; 3] {
    let [x, y, z] = scene.gravity;
    let norm = (x * x + y * y + z * z).sqrt();
    if norm > 0.0 {
        [-x / norm, -y / norm, -z / norm]
    } else {
        [0.0, 1.0, 0.0]
    }
}

/// Largest horizontal displacement of a dynamic body from where the scene put it, and the
/// lowest dynamic body's centre along the up axis, in meters.
pub(super) fn drift_and_lowest(scene: &Scene, positions: &[[f32; 3]]) -> (f64, f64) {
    let up = up_axis(scene);
    let dot = |a: [f32; 3], b: [f32; 3]| {
        f64::from(a[0]) * f64::from(b[0])
            + f64::from(a[1]) * f64::from(b[1])
            + f64::from(a[2]) * f64::from(b[2])
    };
    let mut drift: f64 = 0.0;
    let mut lowest = f64::INFINITY;
    for (spec, &p) in scene.bodies.iter().zip(positions) {
        if !spec.is_dynamic() {
            continue;
        }
        let d = [
            p[0] - spec.position[0],
            p[1] - spec.position[1],
            p[2] - spec.position[2],
        ];
        let along = dot(d, up);
        let total = dot(d, d);
        drift = drift.max((total - along * along).max(0.0).sqrt());
        lowest = lowest.min(dot(p, up));
    }
    (drift, lowest)
}

/// Writes the scenes as JSON (tumble-scenes' schema, compact) into `dir`.
pub(super) fn write_scenes(dir: &std::path::Path, names: &[String]) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("creating {}: {e}", dir.display()))?;
    for name in names {
        match scene_named(name) {
            Ok(scene) => {
                let path = dir.join(format!("{name}.json"));
                let text = serde_json::to_string(&scene).map_err(|e| e.to_string())?;
                std::fs::write(&path, text)
                    .map_err(|e| format!("writing {}: {e}", path.display()))?;
                println!("wrote {} ({} bodies)", path.display(), scene.bodies.len());
            }
            Err(e) => println!("{name}: {e}"),
        }
    }
    Ok(())
}
