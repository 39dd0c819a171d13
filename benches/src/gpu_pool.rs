//! The effect pool ([`crate::effect_pool`]) as solver bodies for a [`GpuWorld`], so the GPU
//! sleep measurement steps the scene the CPU one does, without the facade in between.

use tumble_geometry::{Cuboid, Pose, Real, Vec3};
use tumble_gpu::solver::Effects;
use tumble_gpu::step::{GpuWorld, GpuWorldConfig, ReadRequest};
use tumble_gpu::{GpuContext, GpuError};

use tumble_solver::{Body, BodyKind, BodyState, DEFAULT_FRICTION, Material};

use crate::effect_pool::pool_layout;

/// The facade's default density (kg/m^3), which the CPU pool's cubes get.
const DENSITY: Real = 1.0;

/// The pool's bodies (the walls, then `cubes` unit cubes) under standard friction.
pub fn gpu_pool_bodies(cubes: usize) -> Vec<Body> {
    let layout = pool_layout(cubes);
    let material = Material {
        friction: DEFAULT_FRICTION,
        restitution: 0.0,
    };
    let body = |kind, half: Vec3, pose: Pose| {
        Body::new(kind, Cuboid::new(half), pose, DENSITY, material).expect("valid pool body")
    };
    let walls = layout.walls.iter().map(|&(half, centre)| {
        body(
            BodyKind::Fixed,
            half,
            Pose::translation(centre.x, centre.y, centre.z),
        )
    });
    let half = Vec3::repeat(tumble::DEFAULT_HALF_EXTENTS);
    let cubes = layout
        .cubes
        .iter()
        .map(|&pose| body(BodyKind::Dynamic, half, pose));
    walls.chain(cubes).collect()
}

/// How a pool world runs.
#[derive(Clone, Copy, Debug)]
pub struct PoolRun {
    /// The sleep stage on.
    pub sleep: bool,
    /// Idle steps skipped (see `tumble_gpu::step::idle`); off records every stage.
    pub skip_idle: bool,
    /// GPU timestamps per stage (where the device has them).
    pub timestamps: bool,
}

/// A GPU world holding the pool of `cubes` cubes at rest in the air, run as `run` says.
pub fn gpu_pool(ctx: &GpuContext, cubes: usize, run: PoolRun) -> GpuWorld {
    let PoolRun {
        sleep,
        skip_idle,
        timestamps,
    } = run;
    let bodies = gpu_pool_bodies(cubes);
    let config = GpuWorldConfig {
        timestamps,
        skip_idle_steps: skip_idle,
        ..Default::default()
    };
    let mut world = GpuWorld::new(ctx, config).expect("a valid config");
    world
        .set_bodies(&bodies, &vec![BodyState::default(); bodies.len()])
        .expect("valid bodies");
    let effects = Effects {
        sleep,
        ..world.effects()
    };
    world.set_effects(effects).expect("effects build");
    world
}

/// The manifolds with points in `world` after its last step, and their points, read back now.
pub fn contact_counts(world: &mut GpuWorld) -> Result<(usize, u32), GpuError> {
    let snapshot = world.read_now(ReadRequest {
        contacts: true,
        ..Default::default()
    })?;
    let contacts = snapshot.contacts.as_ref();
    let manifolds = contacts.map_or(0, |c| c.manifolds.iter().filter(|m| m.len > 0).count());
    let points = contacts.map_or(0, |c| c.manifolds.iter().map(|m| m.len).sum());
    Ok((manifolds, points))
}
