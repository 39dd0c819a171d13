//! Effects a scene does not use are skipped, and skipping changes only the time: for each
//! effect, a scene without it steps to the same bits with the effect forced on and forced off.
//! The other side: for each effect, a scene that uses it moves differently with it forced off,
//! as leaving that physics out must (on the CPU, and on the GPU where the effect has a switch).

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

// ---------------------------------------------------------------------------------------------
// The other side of the contract: an effect the scene uses, forced off, changes the motion
// as leaving that physics out must. Each check takes the backend's base config, so the CPU
// tests here and the GPU ones below run the same scenes against the same bounds.
// ---------------------------------------------------------------------------------------------

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

/// A fixed 40 x 1 x 40 m floor whose top is y = 0, of friction `friction`.
fn floor(world: &mut World, friction: Real) {
    world
        .add_body(
            BodyDesc::fixed()
                .cuboid(Vec3::new(20.0, 0.5, 20.0))
                .translation(0.0, -0.5, 0.0)
                .friction(friction),
        )
        .unwrap();
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

/// Friction forced off lets a cube thrown along the rough floor slide on.
fn check_friction(base: WorldConfig) {
    let slide = |switch| {
        let mut world = world_with(base, |e, s| e.friction = s, switch);
        pile_single(&mut world);
        for _ in 0..36 {
            world.step().unwrap();
        }
        world.linear_velocity(world.handles()[1]).unwrap().x
    };
    // mu g = 5.9 m/s^2 stops the 3 m/s cube in 0.51 s, inside the 0.6 s run; without friction
    // rows nothing acts along the floor and it keeps its speed up to round-off.
    let (on, off) = (slide(EffectSwitch::Auto), slide(EffectSwitch::Off));
    assert!(
        on.abs() < 0.05,
        "with friction the cube still slides at {on} m/s"
    );
    assert!(
        (off - 3.0).abs() < 1e-3,
        "friction off: the cube slides at {off} m/s"
    );
}

/// Drop height of the bouncing cube's bottom face, m, and its restitution.
const DROP: Real = 1.0;
const BOUNCE: Real = 0.5;

/// Restitution forced off stops a dropped bouncy cube's bounce.
fn check_restitution(base: WorldConfig) {
    let apex = |switch| {
        let mut world = world_with(base, |e, s| e.restitution = s, switch);
        floor(&mut world, tumble::solver::DEFAULT_FRICTION);
        let cube = world
            .add_body(
                BodyDesc::dynamic()
                    .translation(0.0, 0.5 + DROP, 0.0)
                    .restitution(BOUNCE),
            )
            .unwrap();
        let (mut landed, mut apex) = (false, Real::NEG_INFINITY);
        // 0.75 s: the fall takes 0.45 s and the rise to the apex 0.23 s.
        for _ in 0..45 {
            world.step().unwrap();
            let height = world.pose(cube).unwrap().translation.y - 0.5;
            // The impact is the first step that ends low and no longer falling fast.
            landed |= world.linear_velocity(cube).unwrap().y > -0.5 && height < 0.5 * DROP;
            if landed {
                apex = apex.max(height);
            }
        }
        apex
    };
    let (on, off) = (apex(EffectSwitch::Auto), apex(EffectSwitch::Off));
    // Restitution e sends the cube back up at e times its impact speed, to e^2 times its drop
    // height (0.25 m) at most; the soft contact absorbs part of the impact first (measured
    // 0.21 m), hence the lower bound of 70%.
    let ideal = BOUNCE * BOUNCE * DROP;
    assert!(
        on > 0.7 * ideal && on <= ideal,
        "bounced {on} m, ideal {ideal} m"
    );
    // Without it the contact only stops the fall: what rises is the soft contact pushing out
    // its last step's overlap (measured 0.6 mm).
    assert!(off < 0.01, "restitution off: bounced {off} m");
}

/// Gravity forced off leaves a cube let go in the air where it is.
fn check_gravity(base: WorldConfig) {
    let start = Vec3::new(0.0, 5.0, 0.0);
    let steps = 30;
    let end = |switch| {
        let mut world = world_with(base, |e, s| e.gravity = s, switch);
        floor(&mut world, tumble::solver::DEFAULT_FRICTION);
        let cube = world
            .add_body(BodyDesc::dynamic().translation(start.x, start.y, start.z))
            .unwrap();
        for _ in 0..steps {
            world.step().unwrap();
        }
        (
            world.pose(cube).unwrap().translation.vector,
            world.linear_velocity(cube).unwrap(),
        )
    };
    // Semi-implicit Euler over n substeps of h drops the cube by g h^2 n (n + 1) / 2 (1.23 m
    // in 0.5 s, still in the air); f32 round-off stays far below the 1 mm bound.
    let (on, _) = end(EffectSwitch::Auto);
    let substeps = base.solver.substeps as Real;
    let (n, h) = (steps as Real * substeps, base.dt / substeps);
    let expected = -base.gravity.y * h * h * n * (n + 1.0) / 2.0;
    let dropped = start.y - on.y;
    assert!(
        (dropped - expected).abs() < 1e-3,
        "fell {dropped} m, expected {expected} m"
    );
    // Without it nothing acts on the cube: it stays exactly where it was, at rest.
    let (off, v) = end(EffectSwitch::Off);
    assert_eq!(off, start, "gravity off: the cube moved");
    assert_eq!(v, Vec3::zeros(), "gravity off: the cube moves");
}

/// Speed of the creeping cube, m/s: under the sleep threshold.
const CREEP: Real = 0.03;
const _: () = assert!(CREEP < tumble::LINEAR_SLEEP_TOLERANCE);

/// Sleep forced off lets a cube creeping on a frictionless floor, too slowly to stay awake,
/// creep on; with sleep on it stops once it has been slow for [`tumble::TIME_TO_SLEEP`].
fn check_sleep(base: WorldConfig) {
    let steps = 120;
    let creep = |switch| {
        let mut world = world_with(base, |e, s| e.sleep = s, switch);
        floor(&mut world, 0.0);
        let cube = world
            .add_body(
                BodyDesc::dynamic()
                    .translation(0.0, 0.5, 0.0)
                    .friction(0.0)
                    .linear_velocity(Vec3::new(CREEP, 0.0, 0.0)),
            )
            .unwrap();
        for _ in 0..steps {
            world.step().unwrap();
        }
        let x = world.pose(cube).unwrap().translation.x;
        let v = world.linear_velocity(cube).unwrap().x;
        let asleep = world.is_sleeping(cube).unwrap();
        (x, v, asleep)
    };
    let dt = base.dt;
    // Asleep, it stopped after resting TIME_TO_SLEEP, having crept CREEP times that (15 mm),
    // give or take a step's 0.5 mm.
    let (x, v, asleep) = creep(EffectSwitch::On);
    assert!(
        asleep && v == 0.0,
        "sleep on: asleep {asleep}, speed {v} m/s"
    );
    let slept_at = CREEP * tumble::TIME_TO_SLEEP;
    assert!(
        (x - slept_at).abs() <= CREEP * dt * 1.5,
        "sleep on: crept {x} m"
    );
    // Awake, nothing slows it: it creeps the whole 2 s, 60 mm, up to round-off.
    let (x, v, asleep) = creep(EffectSwitch::Off);
    assert!(!asleep, "sleep off: the cube sleeps");
    assert!((v - CREEP).abs() < 1e-6, "sleep off: speed {v} m/s");
    let crept = CREEP * dt * steps as Real;
    assert!(
        (x - crept).abs() < 1e-5,
        "sleep off: crept {x} m, expected {crept} m"
    );
}

#[test]
fn friction_forced_off_lets_a_thrown_cube_slide_on() {
    check_friction(WorldConfig::default());
}

#[test]
fn restitution_forced_off_stops_the_bounce() {
    check_restitution(WorldConfig::default());
}

#[test]
fn gravity_forced_off_leaves_a_cube_in_the_air() {
    check_gravity(WorldConfig::default());
}

#[test]
fn sleep_forced_off_lets_a_creeping_cube_creep_on() {
    check_sleep(WorldConfig::default());
}

#[test]
fn rotation_forced_off_stops_every_spin() {
    // The rotation switch decides whether bodies turn at all, on every backend: with it on,
    // a cube spinning at 2 rad/s with an angular damping rate c keeps 2 (1 + h c)^-n after n
    // substeps of h (2 e^-1 = 0.74 rad/s after 1 s at c = 1/s); with it off the spin is
    // zeroed and the cube keeps its attitude.
    let c = 1.0;
    let base = WorldConfig {
        gravity: Vec3::zeros(),
        ..Default::default()
    };
    let spin = |switch| {
        let mut world = world_with(base, |e, s| e.rotation = s, switch);
        let cube = world
            .add_body(
                BodyDesc::dynamic()
                    .angular_velocity(Vec3::new(0.0, 2.0, 0.0))
                    .angular_damping(c),
            )
            .unwrap();
        for _ in 0..60 {
            world.step().unwrap();
        }
        let turned = world.pose(cube).unwrap().rotation.angle();
        (world.angular_velocity(cube).unwrap().y, turned)
    };
    let substeps = base.solver.substeps as Real;
    let (n, h) = (60.0 * substeps, base.dt / substeps);
    let damped = 2.0 * (1.0 + h * c).powf(-n);
    let (on, turned_on) = spin(EffectSwitch::Auto);
    assert!(
        (on - damped).abs() < 1e-4,
        "spin {on} rad/s, expected {damped}"
    );
    // About 2 (1 - e^-1) = 1.26 rad in the second.
    assert!(turned_on > 1.0, "turned {turned_on} rad");
    let (off, turned_off) = spin(EffectSwitch::Off);
    assert_eq!(off, 0.0, "rotation off: spin {off} rad/s");
    assert_eq!(turned_off, 0.0, "rotation off: turned {turned_off} rad");
}

#[test]
fn rotation_forced_off_keeps_a_tipped_cube_from_turning() {
    check_tipped_cube(WorldConfig::default());
}

/// Tilt of the tipped cube about z, rad: under 45 degrees its centre lies beside the edge
/// it stands on, over the face it was tipped from, so gravity turns it back onto that
/// face.
const TILT: Real = 0.6;

/// With rotation off contacts cannot turn a body either (its inverse inertia is zero for the
/// step): a cube stood on one edge falls back flat with rotation, and stays tilted exactly as
/// it was without.
fn check_tipped_cube(base: WorldConfig) {
    // The edge 1 mm above the floor: the centre is 0.5 (cos + sin) above it.
    let y = 0.5 * (TILT.cos() + TILT.sin()) + 0.001;
    let start = Rot::from_euler_angles(0.0, 0.0, TILT);
    let tip = |switch| {
        let mut world = world_with(base, |e, s| e.rotation = s, switch);
        floor(&mut world, tumble::solver::DEFAULT_FRICTION);
        let pose = Pose::from_parts(Vec3::new(0.0, y, 0.0).into(), start);
        let cube = world.add_body(BodyDesc::dynamic().pose(pose)).unwrap();
        let mut turned: Real = 0.0;
        for _ in 0..45 {
            world.step().unwrap();
            turned = turned.max(world.pose(cube).unwrap().rotation.angle_to(&start));
        }
        turned
    };
    // With rotation it turns through its whole tilt (and rocks a little past flat:
    // measured 0.637 rad); 90% of it leaves room for the landing.
    let on = tip(EffectSwitch::Auto);
    assert!(on > 0.9 * TILT, "turned {on} rad, tilt {TILT} rad");
    let off = tip(EffectSwitch::Off);
    assert!(off < 1e-6, "rotation off: the cube turned {off} rad");
}

#[test]
fn kinematic_handling_forced_off_lets_a_pusher_pass_a_sleeping_cube() {
    // With sleep on, a sleeping cube is out of the step, and only the kinematic handling
    // wakes it when a moving kinematic body reaches it. A kinematic box moving at 1 m/s
    // reaches the cube asleep on the floor after 1.5 s: with the handling it pushes the cube
    // ahead of it (to x = 2.5 m when the box is at 1.5 m after 4 s); without it the box
    // passes through, and the cube sleeps on where it fell asleep.
    let mut base = WorldConfig::default();
    base.effects.sleep = EffectSwitch::On;
    let push = |switch| {
        let mut world = world_with(base, |e, s| e.kinematic = s, switch);
        floor(&mut world, tumble::solver::DEFAULT_FRICTION);
        let cube = world
            .add_body(BodyDesc::dynamic().translation(0.0, 0.5, 0.0))
            .unwrap();
        world
            .add_body(
                BodyDesc::kinematic()
                    .translation(-2.5, 0.55, 0.0)
                    .linear_velocity(Vec3::new(1.0, 0.0, 0.0)),
            )
            .unwrap();
        let mut slept = false;
        for _ in 0..240 {
            world.step().unwrap();
            slept |= world.is_sleeping(cube).unwrap();
        }
        let x = world.pose(cube).unwrap().translation.x;
        let asleep = world.is_sleeping(cube).unwrap();
        assert!(
            slept,
            "{switch:?}: the cube never slept before the box came"
        );
        (x, asleep)
    };
    let (x, _) = push(EffectSwitch::Auto);
    assert!(
        (x - 2.5).abs() < 0.05,
        "pushed to {x} m, the box's front is at 2.5 m"
    );
    let (x, asleep) = push(EffectSwitch::Off);
    assert!(
        asleep && x.abs() < 1e-6,
        "handling off: cube at {x} m, asleep {asleep}"
    );
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

    // The other side on the GPU step (the facade's path: the fused solver on a small scene;
    // gpu_wide_effects.rs checks the wide one): the same scenes and bounds as on the CPU.
    // Kinematic handling has no GPU switch (its sleep stage always checks kinematic bodies).

    #[test]
    fn friction_forced_off_lets_a_thrown_cube_slide_on() {
        if let Some(base) = gpu_config(G) {
            check_friction(base);
        }
    }

    #[test]
    fn restitution_forced_off_stops_the_bounce() {
        if let Some(base) = gpu_config(G) {
            check_restitution(base);
        }
    }

    #[test]
    fn gravity_forced_off_leaves_a_cube_in_the_air() {
        if let Some(base) = gpu_config(G) {
            check_gravity(base);
        }
    }

    #[test]
    fn sleep_forced_off_lets_a_creeping_cube_creep_on() {
        if let Some(base) = gpu_config(G) {
            check_sleep(base);
        }
    }

    #[test]
    fn rotation_forced_off_keeps_a_tipped_cube_from_turning() {
        if let Some(base) = gpu_config(G) {
            check_tipped_cube(base);
        }
    }
}
