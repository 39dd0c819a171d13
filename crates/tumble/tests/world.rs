//! The facade's behaviour: handles, kinematic bodies, impulses, locks, restitution, contact
//! reports, scenes. Each test is a small scene of a few bodies and at most a few seconds.

use tumble::prelude::*;

const G: Real = 9.81;
const DT: Real = 1.0 / 60.0;

fn world() -> World {
    World::new(WorldConfig::default()).unwrap()
}

/// A fixed floor whose top face is at y = 0.
fn floor(world: &mut World) -> BodyHandle {
    world
        .add_body(
            BodyDesc::fixed()
                .cuboid(Vec3::new(20.0, 0.5, 20.0))
                .translation(0.0, -0.5, 0.0),
        )
        .unwrap()
}

fn steps(world: &mut World, n: usize) {
    for _ in 0..n {
        world.step().unwrap();
    }
}

#[test]
fn handles_are_never_reused_and_removed_bodies_leave_the_world() {
    let mut w = world();
    let a = w.add_body(BodyDesc::dynamic()).unwrap();
    let b = w
        .add_body(BodyDesc::dynamic().translation(3.0, 0.0, 0.0))
        .unwrap();
    w.remove_body(a).unwrap();
    let c = w
        .add_body(BodyDesc::dynamic().translation(6.0, 0.0, 0.0))
        .unwrap();
    assert_ne!(a, c);
    assert_eq!(w.body_count(), 2);
    assert_eq!(w.pose(a), Err(Error::RemovedHandle(a)));
    assert_eq!(w.remove_body(a), Err(Error::RemovedHandle(a)));
    // The survivors kept their own poses through the reshuffle of the dense arrays.
    assert_eq!(w.pose(b).unwrap().translation.x, 3.0);
    assert_eq!(w.pose(c).unwrap().translation.x, 6.0);
}

#[test]
fn removing_the_support_lets_a_resting_box_fall() {
    let mut w = world();
    let ground = floor(&mut w);
    let base = w
        .add_body(BodyDesc::dynamic().translation(0.0, 0.5, 0.0))
        .unwrap();
    let top = w
        .add_body(BodyDesc::dynamic().translation(0.0, 1.5, 0.0))
        .unwrap();
    steps(&mut w, 30);
    assert!(w.contact_pairs().contains(&(base, top)));
    w.remove_body(base).unwrap();
    assert!(
        w.contact_pairs()
            .iter()
            .all(|&(a, b)| a != base && b != base)
    );
    // Free fall of 1 m from rest takes sqrt(2 / g) = 0.45 s; after 1 s the top box rests on
    // the floor, its centre half a metre up (within the few millimetres of contact overlap).
    steps(&mut w, 60);
    let y = w.pose(top).unwrap().translation.y;
    assert!((y - 0.5).abs() < 0.01, "y = {y}");
    assert!(w.contact_pairs().contains(&(ground, top)));
}

#[test]
fn contact_pairs_report_touching_bodies_only() {
    let mut w = world();
    let ground = floor(&mut w);
    let resting = w
        .add_body(BodyDesc::dynamic().translation(0.0, 0.5, 0.0))
        .unwrap();
    let high = w
        .add_body(BodyDesc::dynamic().translation(5.0, 10.0, 0.0))
        .unwrap();
    w.step().unwrap();
    let pairs = w.contact_pairs();
    assert_eq!(pairs, vec![(ground, resting)]);
    assert!(pairs.iter().all(|&(a, b)| a != high && b != high));
    let stats = w.stats();
    assert_eq!(stats.manifolds, 1);
    assert_eq!(
        stats.contact_points, 4,
        "a cube on a floor touches at its four corners"
    );
    assert!(stats.colors >= 1);
    // The reported impulse over the step carries the weight: m g dt within 1% once settled.
    steps(&mut w, 30);
    let carried: Real = w.contacts()[0].normal_impulse();
    assert!((carried - G * DT).abs() < 0.01 * G * DT, "{carried}");
}

#[test]
fn a_kinematic_platform_carries_a_box_and_ignores_it() {
    let mut w = world();
    let platform = w
        .add_body(
            BodyDesc::kinematic()
                .cuboid(Vec3::new(3.0, 0.25, 3.0))
                .translation(0.0, -0.25, 0.0)
                .linear_velocity(Vec3::new(1.0, 0.0, 0.0)),
        )
        .unwrap();
    let rider = w
        .add_body(BodyDesc::dynamic().translation(0.0, 0.5, 0.0))
        .unwrap();
    steps(&mut w, 120);
    // The platform moved exactly with its velocity, unaffected by the load (2 s at 1 m/s).
    let p = w.pose(platform).unwrap().translation.vector;
    assert!((p.x - 2.0).abs() < 1e-4 && (p.y + 0.25).abs() < 1e-6, "{p}");
    assert_eq!(
        w.linear_velocity(platform).unwrap(),
        Vec3::new(1.0, 0.0, 0.0)
    );
    // Friction (mu 0.6) drags the rider along: it matches the platform's speed within 1 cm/s.
    // Starting from rest it slipped while accelerating at mu g, so it lags the platform by
    // v^2 / (2 mu g) = 8.5 cm; 1 cm covers the soft contact's first steps.
    let v = w.linear_velocity(rider).unwrap();
    assert!((v.x - 1.0).abs() < 0.01, "rider speed {v}");
    let x = w.pose(rider).unwrap().translation.x;
    let expected = 2.0 - 1.0 / (2.0 * 0.6 * G);
    assert!(
        (x - expected).abs() < 0.01,
        "rider at {x}, expected {expected}"
    );
}

#[test]
fn a_kinematic_pusher_shoves_a_box_sideways() {
    let mut w = world();
    floor(&mut w);
    let pusher = w
        .add_body(
            BodyDesc::kinematic()
                .cuboid(Vec3::new(0.25, 0.5, 1.0))
                .translation(-1.0, 0.5, 0.0)
                .linear_velocity(Vec3::new(0.5, 0.0, 0.0)),
        )
        .unwrap();
    let box_ = w
        .add_body(BodyDesc::dynamic().translation(0.5, 0.5, 0.0))
        .unwrap();
    steps(&mut w, 180);
    // After 3 s the pusher's face is at -1 + 1.5 + 0.25 = 0.75 m, so the box's centre, held
    // against it, is at 1.25 m (within the contact overlap and the margin).
    let x = w.pose(box_).unwrap().translation.x;
    assert!((x - 1.25).abs() < 0.03, "box at {x}");
    assert_eq!(w.linear_velocity(pusher).unwrap().x, 0.5);
}

#[test]
fn a_kinematic_target_is_reached_in_one_step() {
    let mut w = world();
    let k = w.add_body(BodyDesc::kinematic()).unwrap();
    let target = Pose::new(Vec3::new(0.1, 0.2, -0.1), Vec3::new(0.0, 0.05, 0.0));
    w.set_kinematic_target(k, target).unwrap();
    w.step().unwrap();
    let p = w.pose(k).unwrap();
    // One Euler step along the constant velocities: exact for the translation, and for a
    // 0.05 rad turn the quaternion update is off by (0.05)^3 / 12 ~ 1e-5 rad.
    assert!((p.translation.vector - target.translation.vector).norm() < 1e-5);
    assert!(p.rotation.angle_to(&target.rotation) < 1e-4);
    let d = w.add_body(BodyDesc::dynamic()).unwrap();
    assert_eq!(
        w.set_kinematic_target(d, target).unwrap_err().field(),
        Some("kind")
    );
}

#[test]
fn impulses_change_velocities_by_the_inverse_mass() {
    let mut w = World::new(WorldConfig {
        gravity: Vec3::zeros(),
        ..Default::default()
    })
    .unwrap();
    // A 1 x 2 x 3 box of density 2: m = 12, I = diag(13, 10, 5).
    let b = w
        .add_body(
            BodyDesc::dynamic()
                .cuboid(Vec3::new(0.5, 1.0, 1.5))
                .density(2.0),
        )
        .unwrap();
    w.apply_impulse(b, Vec3::new(0.0, 0.0, 6.0), Point3::new(0.0, 1.0, 0.0))
        .unwrap();
    let v = w.linear_velocity(b).unwrap();
    let omega = w.angular_velocity(b).unwrap();
    // dv = J / m = 0.5 m/s along z; dw = I^-1 (r x J) = (6 / 13, 0, 0).
    assert!((v - Vec3::new(0.0, 0.0, 0.5)).norm() < 1e-5, "{v}");
    assert!(
        (omega - Vec3::new(6.0 / 13.0, 0.0, 0.0)).norm() < 1e-5,
        "{omega}"
    );
    // Fixed bodies ignore impulses.
    let f = w
        .add_body(BodyDesc::fixed().translation(5.0, 0.0, 0.0))
        .unwrap();
    w.apply_impulse(f, Vec3::x(), Point3::new(5.0, 0.0, 0.0))
        .unwrap();
    assert_eq!(w.linear_velocity(f).unwrap(), Vec3::zeros());
}

#[test]
fn locked_rotations_stay_locked_under_an_off_centre_hit() {
    let mut w = world();
    floor(&mut w);
    let b = w
        .add_body(
            BodyDesc::dynamic()
                .translation(0.0, 0.5, 0.0)
                .lock_rotations(),
        )
        .unwrap();
    w.apply_impulse(b, Vec3::new(2.0, 0.0, 0.0), Point3::new(0.0, 0.9, 0.3))
        .unwrap();
    steps(&mut w, 60);
    let p = w.pose(b).unwrap();
    assert_eq!(p.rotation.angle(), 0.0);
    assert!(
        p.translation.x > 0.1,
        "the hit still moves it: {}",
        p.translation.x
    );
}

#[test]
fn a_bouncy_box_rebounds_to_e_squared_of_its_drop() {
    let mut w = world();
    floor(&mut w);
    let drop = 2.0;
    let e = 0.5;
    let b = w
        .add_body(
            BodyDesc::dynamic()
                .translation(0.0, 0.5 + drop, 0.0)
                .restitution(e),
        )
        .unwrap();
    let mut landed = false;
    let mut apex: Real = 0.0;
    for _ in 0..150 {
        w.step().unwrap();
        let y = w.pose(b).unwrap().translation.y - 0.5;
        let vy = w.linear_velocity(b).unwrap().y;
        if vy > 0.0 {
            landed = true;
        }
        if landed {
            apex = apex.max(y);
        }
    }
    // Rebound height e^2 h = 0.5 m. The impact is resolved at the step's start speed, within
    // a step (1/60 s at 6.3 m/s, about 2% of the speed), so 10% of the height is ample while a
    // missing restitution pass (no bounce) or e instead of e^2 (1 m) is far outside.
    let expected = e * e * drop;
    assert!(
        (apex - expected).abs() < 0.1 * expected,
        "apex {apex}, expected {expected}"
    );
}

#[test]
fn a_frictionless_box_keeps_sliding() {
    let mut w = world();
    w.add_body(
        BodyDesc::fixed()
            .cuboid(Vec3::new(50.0, 0.5, 50.0))
            .translation(0.0, -0.5, 0.0)
            .friction(0.0),
    )
    .unwrap();
    let b = w
        .add_body(
            BodyDesc::dynamic()
                .translation(0.0, 0.5, 0.0)
                .friction(0.0)
                .linear_velocity(Vec3::new(3.0, 0.0, 0.0)),
        )
        .unwrap();
    steps(&mut w, 120);
    // With either coefficient zero the contact is frictionless (geometric mean): the speed is
    // kept up to the solver's round-off; friction 0.6 would stop it within 0.6 s.
    let v = w.linear_velocity(b).unwrap();
    assert!((v.x - 3.0).abs() < 0.01, "{v}");
}

#[test]
fn from_scene_builds_every_body_with_the_scene_time_step() {
    let scene = tumble::scenes::mass_ratio();
    let (w, handles) = World::from_scene(&scene, WorldConfig::default()).unwrap();
    assert_eq!(handles.len(), scene.bodies.len());
    assert_eq!(w.body_count(), scene.bodies.len());
    assert_eq!(w.config().dt, scene.dt);
    for (spec, &h) in scene.bodies.iter().zip(&handles) {
        let p = w.pose(h).unwrap().translation.vector;
        assert_eq!([p.x, p.y, p.z], spec.position);
        let mass = w.mass(h).unwrap();
        if spec.is_dynamic() {
            assert!((mass - spec.mass()).abs() < 1e-4 * spec.mass());
        } else {
            assert!(mass.is_infinite());
        }
    }
    let mut bad = scene.clone();
    bad.dt = -1.0;
    assert!(matches!(
        World::from_scene(&bad, WorldConfig::default()),
        Err(Error::InvalidScene(_))
    ));
}

#[test]
fn sequential_and_colored_orders_both_rest_a_stack() {
    for order in [SolveOrder::Sequential, SolveOrder::Colored] {
        let mut w = World::new(WorldConfig {
            solver: SolverConfig {
                order,
                ..Default::default()
            },
            ..Default::default()
        })
        .unwrap();
        floor(&mut w);
        let top = (0..5)
            .map(|i| {
                w.add_body(BodyDesc::dynamic().translation(0.0, 0.5 + i as Real, 0.0))
                    .unwrap()
            })
            .last()
            .unwrap();
        steps(&mut w, 120);
        // Five soft contacts settle a few millimetres in total; the top stays within 1 cm.
        let p = w.pose(top).unwrap().translation.vector;
        assert!(
            (p.y - 4.5).abs() < 0.01 && p.x.abs() < 1e-3,
            "{order:?}: {p}"
        );
    }
}

/// A world without gravity, for tests of free motion.
fn weightless() -> World {
    World::new(WorldConfig {
        gravity: Vec3::zeros(),
        ..Default::default()
    })
    .unwrap()
}

/// Substeps of the default soft step: damping and integration act once per substep.
fn substeps(world: &World) -> i32 {
    world.config().solver.substeps as i32
}

#[test]
fn time_advances_by_dt_every_step() {
    // 1/64 s is exact in binary, so the time after n steps is exactly n / 64: any drift, a
    // skipped step or a doubled one shows at once.
    let mut w = World::new(WorldConfig {
        dt: 1.0 / 64.0,
        ..Default::default()
    })
    .unwrap();
    w.add_body(BodyDesc::dynamic()).unwrap();
    assert_eq!(w.time(), 0.0);
    for n in 1..=200u32 {
        w.step().unwrap();
        assert_eq!(w.time(), f64::from(n) / 64.0, "after {n} steps");
    }
    // At 60 Hz the f32 step 1/60 is not exact; the time is n times that f32 in f64. A clock
    // summed in f32 would be off by about one f32 ulp of the time per step (1e-6 s near 10 s),
    // far above the 1e-12 relative allowed here for the f64 product.
    let mut w = world();
    let dt = f64::from(w.config().dt);
    for n in 1..=600u32 {
        w.step().unwrap();
        let expected = f64::from(n) * dt;
        assert!(
            (w.time() - expected).abs() <= 1e-12 * expected,
            "after {n} steps: {} s, expected {expected} s",
            w.time()
        );
    }
    // f32(1/60) is 1/60 + 7e-10, so 600 steps are 10 s within 1e-6 s.
    assert!(
        (w.time() - 10.0).abs() < 1e-6,
        "600 steps at 60 Hz are 10 s"
    );
}

#[test]
fn max_penetration_is_the_deepest_overlap_of_the_last_step() {
    let mut w = weightless();
    assert_eq!(w.max_penetration(), 0.0, "no step, no contact");
    // Two unit cubes with centres 0.9 m apart overlap by 0.1 m; the contacts of a step are
    // found at its start, so the first step reports exactly that depth (f32 round-off of the
    // 0.9 m offset, a few 1e-8 m, aside).
    w.add_body(BodyDesc::dynamic()).unwrap();
    w.add_body(BodyDesc::dynamic().translation(0.9, 0.0, 0.0))
        .unwrap();
    w.step().unwrap();
    let depth = w.max_penetration();
    assert!(
        (depth - 0.1).abs() < 1e-5,
        "max_penetration {depth}, overlap 0.1"
    );
    let reported = w.contacts()[0].max_depth();
    assert_eq!(depth, reported, "the stat is the deepest reported point");
    // A second pair overlapping by 0.25 m becomes the deepest.
    w.add_body(BodyDesc::dynamic().translation(0.0, 10.0, 0.0))
        .unwrap();
    w.add_body(BodyDesc::dynamic().translation(0.75, 10.0, 0.0))
        .unwrap();
    w.step().unwrap();
    let depth = w.max_penetration();
    assert!(
        (depth - 0.25).abs() < 1e-5,
        "max_penetration {depth}, overlap 0.25"
    );
    // Apart, it is zero: far apart (no manifold), and 1 cm apart, within the 2 cm speculative
    // margin, where the manifold's points have a negative depth that must not be reported.
    for gap in [5.0, 0.01] {
        let mut w = weightless();
        w.add_body(BodyDesc::dynamic()).unwrap();
        w.add_body(BodyDesc::dynamic().translation(1.0 + gap, 0.0, 0.0))
            .unwrap();
        w.step().unwrap();
        let expect_manifold = gap < tumble::DEFAULT_MARGIN;
        assert_eq!(
            w.contacts().len(),
            usize::from(expect_manifold),
            "gap {gap}"
        );
        assert_eq!(w.max_penetration(), 0.0, "gap {gap}");
    }
}

#[test]
fn wake_up_puts_a_sleeping_box_back_under_gravity() {
    let mut config = WorldConfig::default();
    config.effects.sleep = tumble::EffectSwitch::On;
    let mut w = World::new(config).unwrap();
    let ground = floor(&mut w);
    let b = w
        .add_body(BodyDesc::dynamic().translation(0.0, 0.5, 0.0))
        .unwrap();
    // At rest from the start, the box sleeps after TIME_TO_SLEEP (0.5 s, 30 steps).
    let mut n = 0;
    while !w.is_sleeping(b).unwrap() {
        w.step().unwrap();
        n += 1;
        assert!(n <= 60, "the resting box never fell asleep");
    }
    // Woken by hand while resting on the floor, it is awake with a fresh rest timer: it stays
    // awake for almost TIME_TO_SLEEP again before the island sleeps once more.
    w.wake_up(b).unwrap();
    assert!(!w.is_sleeping(b).unwrap());
    assert_eq!(w.sleeping_count(), 0);
    let mut again = 0;
    while !w.is_sleeping(b).unwrap() {
        w.step().unwrap();
        again += 1;
        assert!(again <= 60, "the woken box never slept again");
    }
    assert!(
        again >= 25,
        "slept again after {again} steps: the rest timer was not reset"
    );
    // Removing the floor under the sleeping box wakes it: it lost its support.
    let slept = w.pose(b).unwrap();
    w.remove_body(ground).unwrap();
    assert!(
        !w.is_sleeping(b).unwrap(),
        "the floor went, the box must wake"
    );
    assert_eq!(w.sleeping_count(), 0);
    // Awake, it falls freely. Semi-implicit Euler over K substeps of h: v = -g K h, and the
    // drop is g h^2 K (K + 1) / 2 (1.2331 m after 0.5 s, against 1/2 g t^2 = 1.2263 m): 1 mm
    // is far below either difference and far below any fall at all.
    let steps_awake = 30;
    steps(&mut w, steps_awake);
    let k = (steps_awake as i32 * substeps(&w)) as Real;
    let h = DT / substeps(&w) as Real;
    let v = w.linear_velocity(b).unwrap().y;
    assert!(
        (v + G * k * h).abs() < 1e-4,
        "v {v}, expected {}",
        -G * k * h
    );
    let drop = slept.translation.y - w.pose(b).unwrap().translation.y;
    let expected = G * h * h * k * (k + 1.0) / 2.0;
    assert!(
        (drop - expected).abs() < 1e-3,
        "fell {drop} m, expected {expected} m"
    );
    // A fresh rest timer: it does not fall back asleep in mid-air.
    assert!(!w.is_sleeping(b).unwrap());
}

#[test]
fn a_locked_rotation_axis_stays_still_while_the_free_axes_turn() {
    let mut w = weightless();
    // A unit cube of density 1: m = 1, I = 1/6 about every axis. Rotation about world x is
    // locked, y and z are free.
    let b = w
        .add_body(BodyDesc::dynamic().lock_rotation_axes([true, false, false]))
        .unwrap();
    // An impulse J = (1, 0, 2) at r = (0.3, 0.4, 0) from the centre has the torque impulse
    // r x J = (0.8, -0.6, -0.4): free, the cube would spin at 6 (r x J) = (4.8, -3.6, -2.4).
    w.apply_impulse(b, Vec3::new(1.0, 0.0, 2.0), Point3::new(0.3, 0.4, 0.0))
        .unwrap();
    let expected = Vec3::new(0.0, -3.6, -2.4);
    let omega = w.angular_velocity(b).unwrap();
    assert_eq!(omega.x, 0.0, "the impulse turned the locked axis: {omega}");
    assert!((omega - expected).norm() < 1e-5, "{omega}");
    // Free motion: a cube has no gyroscopic torque, so the spin stays (0, -3.6, -2.4) and the
    // locked component stays exactly zero every step.
    for _ in 0..60 {
        w.step().unwrap();
        let omega = w.angular_velocity(b).unwrap();
        assert_eq!(omega.x, 0.0, "the locked axis turned: {omega}");
        assert!((omega - expected).norm() < 1e-4, "{omega}");
    }
    // After 1 s the cube has turned |w| t = 4.33 rad about the fixed axis (0, -0.6, -0.4)
    // (normalized). The Cayley update loses (h |w|)^3 / 12, about 2e-7 rad a substep, 1e-4 in
    // all: 1e-3 rad tolerates that, while a locked axis that turned would be off by radians.
    let turned = Rot::from_scaled_axis(expected * (60.0 * DT));
    let rotation = w.pose(b).unwrap().rotation;
    let off = rotation.angle_to(&turned);
    assert!(off < 1e-3, "rotation {off} rad from the expected one");
}

#[test]
fn damping_scales_velocities_by_one_over_one_plus_h_c_each_substep() {
    // Damping is implicit per substep h: v <- v / (1 + h c). Over n substeps v = v0 (1 + h c)^-n.
    let mut w = weightless();
    let (c_lin, c_ang) = (2.0, 1.5);
    let v0 = Vec3::new(3.0, 0.0, -1.0);
    let w0 = Vec3::new(0.0, 4.0, 0.0);
    // A cube spinning about y: no gyroscopic torque, only damping changes its spin.
    let b = w
        .add_body(
            BodyDesc::dynamic()
                .linear_velocity(v0)
                .angular_velocity(w0)
                .linear_damping(c_lin)
                .angular_damping(c_ang),
        )
        .unwrap();
    let free = w
        .add_body(
            BodyDesc::dynamic()
                .translation(0.0, 10.0, 0.0)
                .linear_velocity(v0)
                .angular_velocity(w0),
        )
        .unwrap();
    let n_steps = 60;
    steps(&mut w, n_steps);
    let n = n_steps as i32 * substeps(&w);
    let h = f64::from(DT) / f64::from(substeps(&w));
    let lin = (1.0 + h * f64::from(c_lin)).powi(-n) as Real;
    let ang = (1.0 + h * f64::from(c_ang)).powi(-n) as Real;
    // After 1 s: lin = 0.13609, ang = 0.22383. The continuous exp(-c t) gives 0.13534 and
    // 0.22313, damping once per step instead of per substep 0.13982 and 0.22728: 0.3% and more
    // away. 360 f32 products round to about 2e-5 relative; 1e-4 separates both.
    let v = w.linear_velocity(b).unwrap();
    let omega = w.angular_velocity(b).unwrap();
    assert!(
        (v - v0 * lin).norm() < 1e-4 * v0.norm() * lin,
        "v {v}, expected {}",
        v0 * lin
    );
    assert!(
        (omega - w0 * ang).norm() < 1e-4 * w0.norm() * ang,
        "w {omega}, expected {}",
        w0 * ang
    );
    // The undamped twin keeps both exactly: damping is per body.
    assert_eq!(w.linear_velocity(free).unwrap(), v0);
    assert!((w.angular_velocity(free).unwrap() - w0).norm() < 1e-6);
}

#[test]
fn set_kinematic_target_rejects_nan_and_stale_handles_and_changes_nothing() {
    let mut w = world();
    floor(&mut w);
    let k = w
        .add_body(
            BodyDesc::kinematic()
                .translation(0.0, 2.0, 0.0)
                .linear_velocity(Vec3::new(0.5, 0.0, 0.0)),
        )
        .unwrap();
    w.add_body(BodyDesc::dynamic().translation(3.0, 0.5, 0.0))
        .unwrap();
    steps(&mut w, 5);
    let snapshot = |w: &World| -> Vec<(Pose, Vec3, Vec3)> {
        w.handles()
            .iter()
            .map(|&h| {
                (
                    w.pose(h).unwrap(),
                    w.linear_velocity(h).unwrap(),
                    w.angular_velocity(h).unwrap(),
                )
            })
            .collect()
    };
    let before = snapshot(&w);
    let nan = Real::NAN;
    let mut bad_rotation = Pose::identity();
    bad_rotation.rotation =
        Rot::new_unchecked(tumble::nalgebra::Quaternion::new(nan, 0.0, 0.0, 0.0));
    for target in [Pose::translation(0.0, nan, 0.0), bad_rotation] {
        let err = w.set_kinematic_target(k, target).unwrap_err();
        assert_eq!(err.field(), Some("pose"), "{err}");
        assert!(err.to_string().contains("NaN"), "the value is named: {err}");
        assert_eq!(snapshot(&w), before);
    }
    // The platform keeps the velocity it had: after one more step it moved 0.5 m/s * dt.
    let x = w.pose(k).unwrap().translation.x;
    w.step().unwrap();
    let moved = w.pose(k).unwrap().translation.x - x;
    assert!((moved - 0.5 * DT).abs() < 1e-6, "moved {moved}");
    // A removed kinematic body: the error names its handle, and nothing else changes.
    let gone = w
        .add_body(BodyDesc::kinematic().translation(-3.0, 2.0, 0.0))
        .unwrap();
    w.remove_body(gone).unwrap();
    let before = snapshot(&w);
    let target = Pose::translation(-3.0, 3.0, 0.0);
    assert_eq!(
        w.set_kinematic_target(gone, target),
        Err(Error::RemovedHandle(gone))
    );
    assert_eq!(snapshot(&w), before);
    assert_eq!(w.body_count(), 3);
}

#[test]
fn body_getters_err_on_removed_handles_and_read_the_right_body() {
    let mut w = weightless();
    let doomed = w.add_body(BodyDesc::dynamic()).unwrap();
    // A 1 x 2 x 3 box of density 2: m = 12, I = diag(13, 10, 5).
    let brick = w
        .add_body(
            BodyDesc::dynamic()
                .cuboid(Vec3::new(0.5, 1.0, 1.5))
                .density(2.0)
                .translation(5.0, 0.0, 0.0)
                .linear_velocity(Vec3::new(1.0, 2.0, 0.0))
                .angular_velocity(Vec3::new(0.5, 0.0, 0.2)),
        )
        .unwrap();
    let wall = w
        .add_body(
            BodyDesc::fixed()
                .cuboid(Vec3::new(0.1, 2.0, 3.0))
                .translation(-5.0, 0.0, 0.0),
        )
        .unwrap();
    // The removal moves the last body (the wall) into the removed one's dense slot.
    w.remove_body(doomed).unwrap();
    let removed = Error::RemovedHandle(doomed);
    assert_eq!(w.kind(doomed), Err(removed.clone()));
    assert_eq!(w.mass(doomed), Err(removed.clone()));
    assert_eq!(w.half_extents(doomed), Err(removed.clone()));
    assert_eq!(w.angular_momentum(doomed), Err(removed.clone()));
    assert_eq!(w.kinetic_energy(doomed), Err(removed));
    // The survivors answer for themselves, not for whoever took the removed slot.
    assert_eq!(w.kind(brick), Ok(BodyKind::Dynamic));
    assert_eq!(w.kind(wall), Ok(BodyKind::Fixed));
    assert!((w.mass(brick).unwrap() - 12.0).abs() < 1e-4);
    assert_eq!(w.mass(wall), Ok(Real::INFINITY));
    assert_eq!(w.half_extents(brick), Ok(Vec3::new(0.5, 1.0, 1.5)));
    assert_eq!(w.half_extents(wall), Ok(Vec3::new(0.1, 2.0, 3.0)));
    // L = I w = (13 * 0.5, 0, 5 * 0.2); E = m v^2 / 2 + w.Iw / 2 = 30 + 1.725.
    let l = w.angular_momentum(brick).unwrap();
    assert!((l - Vec3::new(6.5, 0.0, 1.0)).norm() < 1e-4, "{l}");
    let e = w.kinetic_energy(brick).unwrap();
    assert!((e - 31.725).abs() < 1e-3, "{e}");
    assert_eq!(w.angular_momentum(wall), Ok(Vec3::zeros()));
    assert_eq!(w.kinetic_energy(wall), Ok(0.0));
}

/// A box on a 20-degree fixed ramp, the two with different frictions: the box's acceleration
/// down the slope, from the velocity gained between 0.5 s and 2 s.
fn ramp_slide(box_friction: Real, ramp_friction: Real) -> Real {
    let mut w = world();
    let rot = Rot::from_axis_angle(&Vec3::z_axis(), RAMP_DEG.to_radians());
    // A 20 m long ramp (local x), rising toward +x; the box starts 5 m up its slope so that it
    // stays on it for the whole run (3 m slid in 2 s, under 6 m even with the min mix).
    w.add_body(
        BodyDesc::fixed()
            .cuboid(Vec3::new(10.0, 0.5, 2.0))
            .pose(Pose::from_parts(Vec3::zeros().into(), rot))
            .friction(ramp_friction),
    )
    .unwrap();
    let start = rot * Vec3::new(5.0, 1.0, 0.0);
    let b = w
        .add_body(
            BodyDesc::dynamic()
                .pose(Pose::from_parts(start.into(), rot))
                .friction(box_friction),
        )
        .unwrap();
    let down = rot * Vec3::new(-1.0, 0.0, 0.0);
    // The first 0.5 s let the soft contact, which starts without impulse, take the weight.
    steps(&mut w, 30);
    let v0 = w.linear_velocity(b).unwrap().dot(&down);
    steps(&mut w, 90);
    let v1 = w.linear_velocity(b).unwrap().dot(&down);
    (v1 - v0) / (90.0 * DT)
}

/// The ramp's slope, degrees.
const RAMP_DEG: Real = 20.0;

#[test]
fn a_box_on_a_ramp_of_another_friction_slides_with_the_geometric_mean() {
    // Box 0.05 on ramp 0.8 (and the other way round): sqrt(0.05 * 0.8) = 0.2 < tan 20 = 0.364,
    // so it slides at g (sin 20 - 0.2 cos 20) = 1.5115 m/s^2. The other rules: min 0.05 gives
    // 2.894, the harmonic mean 2ab / (a + b) = 0.0941 gives 2.488, and the arithmetic mean
    // 0.425 and max 0.8 exceed tan 20, so the box would stick (0). 5% (0.076 m/s^2, the
    // tolerance of the equal-friction ramp check) is a mu within 0.008 of 0.2.
    let angle = RAMP_DEG.to_radians();
    let coulomb = |mu: Real| G * (angle.sin() - mu * angle.cos());
    let expected = coulomb((0.05 as Real * 0.8).sqrt());
    for (a, b) in [(0.05, 0.8), (0.8, 0.05)] {
        let measured = ramp_slide(a, b);
        assert!(
            (measured - expected).abs() < 0.05 * expected,
            "box {a} on ramp {b}: slid at {measured} m/s^2, sqrt mix says {expected} \
             (min {}, harmonic {})",
            coulomb(0.05),
            coulomb(2.0 * 0.04 / 0.85)
        );
    }
}
