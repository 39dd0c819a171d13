//! The other side of the contract: an effect the scene uses, forced off, changes the motion
//! as leaving that physics out must. Each check takes the backend's base config, so the CPU
//! tests here and the GPU ones in `gpu.rs` run the same scenes against the same bounds.

use super::*;
use tumble_tests::effect_bounds::{
    Apex, BOUNCE, DROP, TILT, assert_free_fall, assert_friction_stops_the_slide,
    assert_restitution_bounces, assert_tipped_cube_turns, tipped_height,
};

/// Friction forced off lets a cube thrown along the rough floor slide on.
pub fn check_friction(base: WorldConfig) {
    let slide = |switch| {
        let mut world = world_with(base, |e, s| e.friction = s, switch);
        pile_single(&mut world);
        steps(&mut world, 36);
        world.linear_velocity(world.handles()[1]).unwrap().x
    };
    let (on, off) = (slide(EffectSwitch::Auto), slide(EffectSwitch::Off));
    assert_friction_stops_the_slide(on, off);
}

/// Restitution forced off stops a dropped bouncy cube's bounce.
pub fn check_restitution(base: WorldConfig) {
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
        let mut apex = Apex::default();
        // 0.75 s: the fall takes 0.45 s and the rise to the apex 0.23 s.
        for _ in 0..45 {
            world.step().unwrap();
            let height = world.pose(cube).unwrap().translation.y - 0.5;
            apex.watch(height, world.linear_velocity(cube).unwrap().y);
        }
        apex.height
    };
    let (on, off) = (apex(EffectSwitch::Auto), apex(EffectSwitch::Off));
    assert_restitution_bounces(on, off);
}

/// Gravity forced off leaves a cube let go in the air where it is.
pub fn check_gravity(base: WorldConfig) {
    let start = Vec3::new(0.0, 5.0, 0.0);
    let count = 30;
    let end = |switch| {
        let mut world = world_with(base, |e, s| e.gravity = s, switch);
        floor(&mut world, tumble::solver::DEFAULT_FRICTION);
        let cube = world
            .add_body(BodyDesc::dynamic().translation(start.x, start.y, start.z))
            .unwrap();
        steps(&mut world, count);
        (
            world.pose(cube).unwrap().translation.vector,
            world.linear_velocity(cube).unwrap(),
        )
    };
    let (on, _) = end(EffectSwitch::Auto);
    let (g, dt, substeps) = (base.gravity.y, base.dt, base.solver.substeps);
    assert_free_fall(start.y - on.y, g, dt, substeps, count);
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
pub fn check_sleep(base: WorldConfig) {
    let count = 120;
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
        steps(&mut world, count);
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
    let crept = CREEP * dt * count as Real;
    assert!(
        (x - crept).abs() < 1e-5,
        "sleep off: crept {x} m, expected {crept} m"
    );
}

/// `#[test] fn $name` running `$check` on the default (CPU) world config.
macro_rules! cpu_tests {
    ($($name:ident => $check:ident;)+) => {
        $(
            #[test]
            fn $name() {
                $check(WorldConfig::default());
            }
        )+
    };
}

cpu_tests! {
    friction_forced_off_lets_a_thrown_cube_slide_on => check_friction;
    restitution_forced_off_stops_the_bounce => check_restitution;
    gravity_forced_off_leaves_a_cube_in_the_air => check_gravity;
    sleep_forced_off_lets_a_creeping_cube_creep_on => check_sleep;
    rotation_forced_off_keeps_a_tipped_cube_from_turning => check_tipped_cube;
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
        steps(&mut world, 60);
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

/// With rotation off contacts cannot turn a body either (its inverse inertia is zero for the
/// step): a cube stood on one edge falls back flat with rotation, and stays tilted exactly as
/// it was without.
pub fn check_tipped_cube(base: WorldConfig) {
    let y = tipped_height();
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
    let (on, off) = (tip(EffectSwitch::Auto), tip(EffectSwitch::Off));
    assert_tipped_cube_turns(on, off);
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
