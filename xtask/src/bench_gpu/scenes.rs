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
    "droppool1m",
];
/// The scenes of `--quick`: small enough for a software rasterizer in a few minutes.
pub(super) const QUICK_SCENES: &[&str] = &["stack20", "pyramid8", "pool10000", "droppool10k"];
/// Layers of the generated box pool: columns of this many unit cubes resting on the floor.
pub(super) const POOL_LAYERS: usize = 16;
/// Horizontal gap between neighbouring columns of the pool, as between the cubes of a
/// pyramid's layer (`tumble_scenes::builders::common::LAYER_GAP`).
pub(super) const POOL_GAP: f32 = builders::common::LAYER_GAP;

/// Layers of the dropped pool ([`drop_pool`]): its boxes start in this many layers of cells.
pub(super) const DROP_POOL_LAYERS: usize = 16;
/// Side of a cell of the dropped pool's start lattice, m: the largest box (1.2 m on a side)
/// with 5 cm to spare on every side, so no two boxes touch at the start.
const DROP_CELL: f32 = 1.3;
/// Smallest and largest half extent of a dropped pool's box along each axis, m.
const DROP_HALF: [f32; 2] = [0.25, 0.6];
/// Gap kept between a box and its cell's side when it is moved off the cell's centre, m.
const DROP_SIDE_GAP: f32 = 0.025;
/// Thickness of the dropped pool's floor and walls, m.
const DROP_WALL: f32 = 1.0;

/// A scene of the benchmark, or why it cannot be built.
pub(super) fn scene_named(name: &str) -> Result<Scene, String> {
    // A count, with `k` (thousands) or `m` (millions) allowed at its end: pool1m, droppool10k.
    let number = |rest: &str| {
        let rest = rest.replace('_', "");
        let (digits, scale) = match rest.strip_suffix(['k', 'K']) {
            Some(d) => (d.to_owned(), 1_000),
            None => match rest.strip_suffix(['m', 'M']) {
                Some(d) => (d.to_owned(), 1_000_000),
                None => (rest, 1),
            },
        };
        digits
            .parse::<usize>()
            .ok()
            .and_then(|n| n.checked_mul(scale))
            .ok_or_else(|| format!("scene {name:?}: expected a number after the kind"))
    };
    if let Some(n) = name.strip_prefix("droppool") {
        return Ok(drop_pool(number(n)?));
    }
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
        "unknown scene {name:?}: stackN, pyramidH, poolN, droppoolN or nexus_pyramidH"
    ))
}

/// The fractional part of `i` times `step`: for irrational steps an evenly spread,
/// reproducible sequence in [0, 1) (one step per quantity that must not repeat the others).
fn spread(i: usize, step: f64) -> f32 {
    ((i as f64 + 1.0) * step).fract() as f32
}

/// `n` boxes of mixed sizes dropped into a walled pool: a fixed floor (top face at y = 0) and
/// four fixed walls around a square of [`DROP_CELL`]-wide cells, one box per cell in
/// [`DROP_POOL_LAYERS`] layers (the top one partly filled). Each box has its own half extents
/// between [`DROP_HALF`]'s bounds along each axis and sits off its cell's centre by its own
/// amount, so the boxes land on each other unevenly, some tip over, and the pile settles in
/// the first second or two; no two boxes touch at the start.
pub fn drop_pool(n: usize) -> Scene {
    let per_layer = n.div_ceil(DROP_POOL_LAYERS).max(1);
    let side = (per_layer as f64).sqrt().ceil() as usize;
    let inner_half = 0.5 * side as f32 * DROP_CELL;
    let wall_height = (DROP_POOL_LAYERS as f32 + 1.0) * DROP_CELL;
    let t = 0.5 * DROP_WALL;
    let outer = inner_half + DROP_WALL;
    let mut scene = Scene::new(
        format!("drop_pool_{n}"),
        format!(
            "{n} boxes of mixed sizes dropped into a walled pool, {side} x {side} cells in \
             {DROP_POOL_LAYERS} layers; they must stay inside it."
        ),
    );
    scene
        .bodies
        .push(BodySpec::fixed([outer, t, outer], [0.0, -t, 0.0]));
    let wall_y = 0.5 * wall_height;
    for sign in [-1.0, 1.0] {
        let x = sign * (inner_half + t);
        scene
            .bodies
            .push(BodySpec::fixed([t, wall_y, outer], [x, wall_y, 0.0]));
        scene
            .bodies
            .push(BodySpec::fixed([outer, wall_y, t], [0.0, wall_y, x]));
    }
    let first = -inner_half + 0.5 * DROP_CELL;
    let [lo, hi] = DROP_HALF;
    // Steps of the R3 low-discrepancy sequence and two more irrationals: independent spreads
    // for the three extents and the two offsets.
    let steps = [
        0.819_172_513,
        0.671_043_606,
        0.549_700_477,
        0.618_033_989,
        0.414_213_562,
    ];
    for i in 0..n {
        let layer = i / (side * side);
        let row = (i / side) % side;
        let col = i % side;
        let half: [f32; 3] = std::array::from_fn(|k| lo + (hi - lo) * spread(i, steps[k]));
        let room = |h: f32| 0.5 * DROP_CELL - h - DROP_SIDE_GAP;
        let dx = (2.0 * spread(i, steps[3]) - 1.0) * room(half[0]);
        let dz = (2.0 * spread(i, steps[4]) - 1.0) * room(half[2]);
        scene.bodies.push(BodySpec::dynamic(
            half,
            [
                first + col as f32 * DROP_CELL + dx,
                (layer as f32 + 0.5) * DROP_CELL,
                first + row as f32 * DROP_CELL + dz,
            ],
        ));
    }
    scene.check = tumble_scenes::SceneCheck::Contained {
        min: [-inner_half, 0.0, -inner_half],
        max: [inner_half, wall_height, inner_half],
    };
    scene
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
