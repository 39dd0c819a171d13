//! Effects a scene does not use are skipped, and skipping changes only the time: for each
//! effect, a scene without it steps to the same bits with the effect forced on and forced off.
//! The other side: for each effect, a scene that uses it moves differently with it forced off,
//! as leaving that physics out must (on the CPU, and on the GPU where the effect has a switch).

use tumble::prelude::*;
use tumble::{EffectOverrides, EffectSwitch};
use tumble_tests::facade::floor_desc;
use tumble_tests::scene_support::thrown_pile_pose;

mod forced_off;
mod gpu;
mod skipped;

/// Steps long enough for boxes to fall, collide, slide and settle (2 s at 60 Hz).
const STEPS: usize = 120;

/// Steps on the GPU backend: 0.5 s, in which the bottom layer lands and the thrown boxes
/// collide, so every stage has work; shorter because lavapipe, the CI adapter, is slow.
const GPU_STEPS: usize = 30;

/// Every bit of every body's pose and velocities.
fn snapshot(world: &World) -> Vec<u32> {
    let mut bits = Vec::new();
    for &h in world.handles() {
        let p = world.pose(h).unwrap();
        let v = world.linear_velocity(h).unwrap();
        let w = world.angular_velocity(h).unwrap();
        let values = p.translation.vector.iter().chain(p.rotation.coords.iter());
        bits.extend(values.chain(v.iter()).chain(w.iter()).map(|x| x.to_bits()));
    }
    bits
}

/// Runs `build` with `switch` on one effect (chosen by `set`), returning the final bits and
/// the effects the world ran.
fn run(
    base: WorldConfig,
    set: fn(&mut EffectOverrides, EffectSwitch),
    switch: EffectSwitch,
    build: fn(&mut World),
) -> (Vec<u32>, tumble::Effects) {
    let mut world = world_with(base, set, switch);
    build(&mut world);
    let effects = world.effects();
    let n = if base.backend == Backend::Cpu {
        STEPS
    } else {
        GPU_STEPS
    };
    steps(&mut world, n);
    (snapshot(&world), effects)
}

/// A world of `base` with one effect set to `switch` (by `set`).
fn world_with(
    base: WorldConfig,
    set: fn(&mut EffectOverrides, EffectSwitch),
    switch: EffectSwitch,
) -> World {
    let mut config = base;
    set(&mut config.effects, switch);
    World::new(config).unwrap()
}

/// Steps `world` `n` times.
fn steps(world: &mut World, n: usize) {
    for _ in 0..n {
        world.step().unwrap();
    }
}

/// A floor and a loose pile of tilted boxes thrown sideways, so contacts, sliding and spin
/// all happen.
fn pile(world: &mut World, friction: Real, lock_rotations: bool) {
    floor(world, friction);
    for i in 0..12 {
        let mut desc = BodyDesc::dynamic()
            .pose(thrown_pile_pose(i))
            .friction(friction)
            .linear_velocity(Vec3::new(1.5, 0.0, 0.5 * (i % 2) as Real))
            .angular_velocity(Vec3::new(0.0, 1.0, 0.3));
        if lock_rotations {
            desc = desc.lock_rotations();
        }
        world.add_body(desc).unwrap();
    }
}

/// A fixed 40 x 1 x 40 m floor whose top is y = 0, of friction `friction`.
fn floor(world: &mut World, friction: Real) {
    world.add_body(floor_desc(20.0).friction(friction)).unwrap();
}

/// The rough floor and a unit cube on it, thrown along x at 3 m/s.
fn pile_single(world: &mut World) {
    floor(world, tumble::solver::DEFAULT_FRICTION);
    world
        .add_body(
            BodyDesc::dynamic()
                .translation(0.0, 0.5, 0.0)
                .linear_velocity(Vec3::new(3.0, 0.0, 0.0)),
        )
        .unwrap();
}
