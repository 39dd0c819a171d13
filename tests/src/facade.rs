//! Bodies for the facade tests and benches: the floor, a fixed slab 1 m thick whose top face
//! is at y = 0, so a unit cube resting on it has its centre at y = 0.5; and unit cubes.

use tumble::prelude::*;

/// The floor slab, `2 half_extent` m square: add it as it is, or with a material first.
pub fn floor_desc(half_extent: Real) -> BodyDesc {
    BodyDesc::fixed()
        .cuboid(Vec3::new(half_extent, 0.5, half_extent))
        .translation(0.0, -0.5, 0.0)
}

/// Adds the floor slab, `2 half_extent` m square, to `world`; its handle.
pub fn add_floor(world: &mut World, half_extent: Real) -> BodyHandle {
    world.add_body(floor_desc(half_extent)).unwrap()
}

/// Adds a unit cube (a dynamic body of the default shape) centred at `(x, y, z)`; its handle.
pub fn cube_at(world: &mut World, x: Real, y: Real, z: Real) -> BodyHandle {
    world
        .add_body(BodyDesc::dynamic().translation(x, y, z))
        .unwrap()
}

/// A world on `backend` with sleep on and the floor slab (20 m half extent), or `None` when the
/// backend needs a GPU and there is none; without an adapter that is a failure under
/// `TUMBLE_REQUIRE_GPU=1`, else a loud "skipped".
pub fn sleepy_world(backend: Backend) -> Option<World> {
    let mut config = WorldConfig::default();
    config.effects.sleep = tumble::EffectSwitch::On;
    config.backend = backend;
    let mut world = match World::new(config) {
        Ok(world) => world,
        Err(e @ tumble::Error::BackendUnavailable { .. })
            if std::env::var("TUMBLE_REQUIRE_GPU").as_deref() != Ok("1") =>
        {
            eprintln!("##### skipped {backend:?}: no GPU adapter ({e}) #####");
            return None;
        }
        Err(e) => panic!("{backend:?}: {e}"),
    };
    add_floor(&mut world, 20.0);
    Some(world)
}

/// Adds the uneven pile of docs/solver.md ("Piles that keep rocking") to `world`: `side` x
/// `side` columns of `layers` cubes of 0.5 m, 0.52 m apart, each cube raised 3 cm per layer,
/// shifted sideways by up to 8 mm and tilted by up to 0.02 rad about each axis (seeded, so the
/// pile is the same every run), so the cubes fall, land unevenly and settle. The cubes'
/// handles, bottom layer first.
pub fn add_uneven_pile(world: &mut World, side: usize, layers: usize) -> Vec<BodyHandle> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let pitch = 0.52;
    let mut cubes = Vec::new();
    for layer in 0..layers {
        for i in 0..side {
            for k in 0..side {
                let centre = Vec3::new(
                    i as Real * pitch + rng.random_range(-0.008..0.008),
                    0.25 + 0.5 * layer as Real + 0.03 * (layer + 1) as Real,
                    k as Real * pitch + rng.random_range(-0.008..0.008),
                );
                let tilt = Vec3::from_fn(|_, _| rng.random_range(-0.02..0.02));
                let desc = BodyDesc::dynamic()
                    .cuboid(Vec3::repeat(0.25))
                    .pose(Pose::new(centre, tilt));
                cubes.push(world.add_body(desc).expect("a valid cube"));
            }
        }
    }
    cubes
}
