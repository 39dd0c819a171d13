//! Effects a scene does not use are skipped, and skipping changes only the time: for each
//! effect, a scene without it steps to the same bits with the effect forced on and forced off.

use tumble::prelude::*;
use tumble::{EffectOverrides, EffectSwitch};

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
    let mut config = base;
    set(&mut config.effects, switch);
    let mut world = World::new(config).unwrap();
    build(&mut world);
    let effects = world.effects();
    let steps = if config.backend == Backend::Cpu {
        STEPS
    } else {
        GPU_STEPS
    };
    for _ in 0..steps {
        world.step().unwrap();
    }
    (snapshot(&world), effects)
}

/// Asserts that the scene does not need the effect (Auto leaves it out) and that forcing it
/// on gives the same bits as leaving it out.
fn same_bits_on_and_off(
    name: &str,
    base: WorldConfig,
    set: fn(&mut EffectOverrides, EffectSwitch),
    get: fn(&tumble::Effects) -> bool,
    build: fn(&mut World),
) {
    let (auto, auto_effects) = run(base, set, EffectSwitch::Auto, build);
    assert!(!get(&auto_effects), "{name}: the scene should not need it");
    let (on, on_effects) = run(base, set, EffectSwitch::On, build);
    assert!(get(&on_effects), "{name}: forced on");
    let (off, _) = run(base, set, EffectSwitch::Off, build);
    assert!(!on.is_empty());
    assert_eq!(on, off, "{name}: forced on and skipped differ");
    assert_eq!(auto, off, "{name}: auto and skipped differ");
}

/// A floor and a loose pile of tilted boxes thrown sideways, so contacts, sliding and spin
/// all happen.
fn pile(world: &mut World, friction: Real, lock_rotations: bool) {
    world
        .add_body(
            BodyDesc::fixed()
                .cuboid(Vec3::new(20.0, 0.5, 20.0))
                .translation(0.0, -0.5, 0.0)
                .friction(friction),
        )
        .unwrap();
    for i in 0..12 {
        let (x, y, z) = (
            (i % 4) as Real * 0.9,
            0.6 + (i / 4) as Real * 1.1,
            0.3 * (i % 3) as Real,
        );
        let tilt = Rot::from_euler_angles(0.1 * i as Real, 0.2, -0.05 * i as Real);
        let mut desc = BodyDesc::dynamic()
            .pose(Pose::from_parts(Vec3::new(x, y, z).into(), tilt))
            .friction(friction)
            .linear_velocity(Vec3::new(1.5, 0.0, 0.5 * (i % 2) as Real))
            .angular_velocity(Vec3::new(0.0, 1.0, 0.3));
        if lock_rotations {
            desc = desc.lock_rotations();
        }
        world.add_body(desc).unwrap();
    }
}

#[test]
fn friction_skipped_in_a_frictionless_pool() {
    same_bits_on_and_off(
        "friction",
        WorldConfig::default(),
        |e, s| e.friction = s,
        |e| e.friction,
        |w| pile(w, 0.0, false),
    );
}

#[test]
fn restitution_skipped_when_nothing_bounces() {
    same_bits_on_and_off(
        "restitution",
        WorldConfig::default(),
        |e, s| e.restitution = s,
        |e| e.restitution,
        |w| pile(w, 0.6, false),
    );
}

#[test]
fn gravity_skipped_in_zero_gravity() {
    let base = WorldConfig {
        gravity: Vec3::zeros(),
        ..Default::default()
    };
    same_bits_on_and_off(
        "gravity",
        base,
        |e, s| e.gravity = s,
        |e| e.gravity,
        |w| pile(w, 0.6, false),
    );
}

#[test]
fn rotation_skipped_when_every_rotation_is_locked() {
    same_bits_on_and_off(
        "rotation",
        WorldConfig::default(),
        |e, s| e.rotation = s,
        |e| e.rotation,
        |w| pile(w, 0.6, true),
    );
}

#[test]
fn kinematic_handling_skipped_without_kinematic_bodies() {
    // With sleep on, kinematic bodies are what the kinematic effect checks.
    let mut base = WorldConfig::default();
    base.effects.sleep = EffectSwitch::On;
    same_bits_on_and_off(
        "kinematic",
        base,
        |e, s| e.kinematic = s,
        |e| e.kinematic,
        |w| pile(w, 0.6, false),
    );
}

#[test]
fn sleep_forced_on_changes_nothing_while_nothing_rests() {
    // Boxes gliding on a frictionless floor never slow down, so no island ever sleeps; the
    // islands are still built each step when sleep is on. Auto means off for sleep.
    same_bits_on_and_off(
        "sleep",
        WorldConfig::default(),
        |e, s| e.sleep = s,
        |e| e.sleep,
        |w| {
            pile(w, 0.0, false);
            for &h in &w.handles().to_vec()[1..] {
                w.set_linear_velocity(h, Vec3::new(2.0, 0.0, 0.0)).unwrap();
            }
        },
    );
}

#[test]
fn forcing_off_an_effect_the_scene_uses_changes_the_motion() {
    // The other side of the contract: friction forced off on a rough floor lets a thrown box
    // slide on at its initial speed, where friction stops it.
    let slide = |switch| {
        let mut config = WorldConfig::default();
        config.effects.friction = switch;
        let mut world = World::new(config).unwrap();
        pile_single(&mut world);
        for _ in 0..STEPS {
            world.step().unwrap();
        }
        world.linear_velocity(world.handles()[1]).unwrap().x
    };
    // mu g = 5.9 m/s^2 stops a 3 m/s box in about 0.5 s; without friction it keeps 3 m/s.
    assert!(slide(EffectSwitch::Auto).abs() < 0.01);
    assert!((slide(EffectSwitch::Off) - 3.0).abs() < 0.01);
}

fn pile_single(world: &mut World) {
    world
        .add_body(
            BodyDesc::fixed()
                .cuboid(Vec3::new(20.0, 0.5, 20.0))
                .translation(0.0, -0.5, 0.0),
        )
        .unwrap();
    world
        .add_body(
            BodyDesc::dynamic()
                .translation(0.0, 0.5, 0.0)
                .linear_velocity(Vec3::new(3.0, 0.0, 0.0)),
        )
        .unwrap();
}

#[test]
fn locked_axes_stay_locked_through_contacts() {
    // A box with x translation and every rotation locked, dropped tilted onto a corner of
    // another box: the impact pushes it sideways and would spin it.
    let mut world = World::new(WorldConfig::default()).unwrap();
    pile_single(&mut world);
    let tilt = Rot::from_euler_angles(0.3, 0.2, 0.4);
    let locked = world
        .add_body(
            BodyDesc::dynamic()
                .pose(Pose::from_parts(Vec3::new(0.6, 2.0, 0.4).into(), tilt))
                .lock_translations([true, false, false])
                .lock_rotations(),
        )
        .unwrap();
    world.step().unwrap();
    let start = world.pose(locked).unwrap();
    for _ in 0..STEPS {
        world.step().unwrap();
        let p = world.pose(locked).unwrap();
        // Locked motion is exactly zero: the velocity is masked before every integration.
        assert_eq!(p.translation.x, start.translation.x);
        assert_eq!(p.rotation, start.rotation);
    }
    // It did fall (y is free) and land: the tilted box's lowest corner is about 0.8 m below
    // its centre, so on the 1 m cube it rests near y = 1.8, 0.2 m below where it started.
    let y = world.pose(locked).unwrap().translation.y;
    assert!(y < start.translation.y - 0.1 && y > 1.0, "y {y}");
    assert!(world.linear_velocity(locked).unwrap().norm() < 0.05);
}

/// The same contract on the GPU step, whose pipelines are specialized per effect set
/// (`override` switches): its step is deterministic, so forced on and skipped give the same
/// bits there too. Needs a GPU or lavapipe; without one it prints a loud "skipped" unless
/// `TUMBLE_REQUIRE_GPU=1`.
mod gpu {
    use super::*;
    use tumble_gpu::GpuContext;

    fn gpu_config(gravity: Vec3) -> Option<WorldConfig> {
        GpuContext::for_tests()?;
        Some(WorldConfig {
            backend: Backend::Gpu,
            gravity,
            ..Default::default()
        })
    }

    const G: Vec3 = Vec3::new(0.0, -tumble::STANDARD_GRAVITY, 0.0);

    #[test]
    fn friction_skipped_in_a_frictionless_pool() {
        if let Some(base) = gpu_config(G) {
            same_bits_on_and_off(
                "gpu friction",
                base,
                |e, s| e.friction = s,
                |e| e.friction,
                |w| pile(w, 0.0, false),
            );
        }
    }

    #[test]
    fn restitution_skipped_when_nothing_bounces() {
        if let Some(base) = gpu_config(G) {
            same_bits_on_and_off(
                "gpu restitution",
                base,
                |e, s| e.restitution = s,
                |e| e.restitution,
                |w| pile(w, 0.6, false),
            );
        }
    }

    #[test]
    fn gravity_skipped_in_zero_gravity() {
        if let Some(base) = gpu_config(Vec3::zeros()) {
            same_bits_on_and_off(
                "gpu gravity",
                base,
                |e, s| e.gravity = s,
                |e| e.gravity,
                |w| pile(w, 0.6, false),
            );
        }
    }

    #[test]
    fn rotation_skipped_when_every_rotation_is_locked() {
        if let Some(base) = gpu_config(G) {
            same_bits_on_and_off(
                "gpu rotation",
                base,
                |e, s| e.rotation = s,
                |e| e.rotation,
                |w| pile(w, 0.6, true),
            );
        }
    }
}
