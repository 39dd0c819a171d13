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
