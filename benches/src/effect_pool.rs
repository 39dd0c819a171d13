//! The pool the effect and sleep benches step: unit cubes dropped in a grid into a walled
//! container, with the materials, locks and gravity chosen per bench, so that a scene can be
//! built that does not need a given effect.

use tumble::prelude::*;
use tumble::{EffectOverrides, EffectSwitch};

/// Grid pitch, m: a unit cube in any orientation fits in a sphere of radius 0.87 m.
const PITCH: Real = 1.8;
/// Height of the lowest layer's centres, m.
const FIRST_LAYER: Real = 1.0;
/// Gap between the grid and the walls, m.
const CLEARANCE: Real = 0.5;

/// What the pool's bodies use.
#[derive(Clone, Copy, Debug)]
pub struct PoolOptions {
    /// Cubes dropped.
    pub cubes: usize,
    /// Friction coefficient of every body (0: a frictionless pool).
    pub friction: Real,
    /// Lock every cube's rotations.
    pub lock_rotations: bool,
    /// Gravity, m/s^2 (along -y).
    pub gravity: Real,
    /// Where the step runs.
    pub backend: Backend,
}

impl Default for PoolOptions {
    /// 1,000 rough cubes under standard gravity.
    fn default() -> Self {
        Self {
            cubes: 1000,
            friction: tumble::solver::DEFAULT_FRICTION,
            lock_rotations: false,
            gravity: tumble::STANDARD_GRAVITY,
            backend: Backend::Cpu,
        }
    }
}

/// Where the pool's bodies go: the container's fixed walls and the dropped cubes.
#[derive(Clone, Debug)]
pub struct PoolLayout {
    /// Half extents and centre of each fixed slab (the floor, then four walls).
    pub walls: Vec<(Vec3, Vec3)>,
    /// Pose of each unit cube, in a grid with its own orientation each.
    pub cubes: Vec<Pose>,
}

/// The layout of a pool of `cubes` unit cubes: shared by the facade's pool and the GPU
/// world's, so the CPU and GPU sleep measurements step the same scene.
pub fn pool_layout(cubes: usize) -> PoolLayout {
    let g = (cubes as f64).cbrt().ceil() as usize;
    let inner = 0.5 * g as Real * PITCH + CLEARANCE;
    let height = FIRST_LAYER + g as Real * PITCH + 1.0;
    let walls = vec![
        (
            Vec3::new(inner + 1.0, 0.5, inner + 1.0),
            Vec3::new(0.0, -0.5, 0.0),
        ),
        (
            Vec3::new(0.5, height, inner + 1.0),
            Vec3::new(inner + 0.5, height, 0.0),
        ),
        (
            Vec3::new(0.5, height, inner + 1.0),
            Vec3::new(-inner - 0.5, height, 0.0),
        ),
        (
            Vec3::new(inner + 1.0, height, 0.5),
            Vec3::new(0.0, height, inner + 0.5),
        ),
        (
            Vec3::new(inner + 1.0, height, 0.5),
            Vec3::new(0.0, height, -inner - 0.5),
        ),
    ];
    let first = -0.5 * (g as Real - 1.0) * PITCH;
    let cubes = (0..cubes)
        .map(|i| {
            let (col, row, layer) = (i % g, (i / g) % g, i / (g * g));
            let centre = Vec3::new(
                first + col as Real * PITCH,
                FIRST_LAYER + layer as Real * PITCH,
                first + row as Real * PITCH,
            );
            // Golden-ratio phases give every cube its own reproducible orientation.
            let phase = (i as Real * 0.618_034).fract();
            let axis = Vec3::new(1.0, phase, 1.0 - phase).normalize();
            let rotation = Rot::from_scaled_axis(axis * phase * std::f32::consts::PI);
            Pose::from_parts(centre.into(), rotation)
        })
        .collect();
    PoolLayout { walls, cubes }
}

/// The pool world with `effects` overriding the derived effects. Panics when the backend is
/// unavailable (a bench has nothing to time then).
pub fn effect_pool(options: PoolOptions, effects: EffectOverrides) -> World {
    let config = WorldConfig {
        gravity: Vec3::new(0.0, -options.gravity, 0.0),
        effects,
        backend: options.backend,
        ..Default::default()
    };
    let mut world = World::new(config).expect("a valid config on an available backend");
    let layout = pool_layout(options.cubes);
    for (half, centre) in layout.walls {
        let desc = BodyDesc::fixed()
            .cuboid(half)
            .translation(centre.x, centre.y, centre.z)
            .friction(options.friction);
        world.add_body(desc).expect("valid wall");
    }
    for pose in layout.cubes {
        let mut desc = BodyDesc::dynamic().pose(pose).friction(options.friction);
        if options.lock_rotations {
            desc = desc.lock_rotations();
        }
        world.add_body(desc).expect("valid cube");
    }
    world
}

/// Overrides with sleep on and every other effect derived.
pub fn with_sleep() -> EffectOverrides {
    EffectOverrides {
        sleep: EffectSwitch::On,
        ..Default::default()
    }
}
