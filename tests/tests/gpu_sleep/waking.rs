//! Falling asleep and waking: settling, dropped boxes, host calls, turning sleep on and off,
//! a kinematic pusher.

use super::*;

#[test]
fn a_settled_pool_falls_asleep_and_then_stops_changing() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let bodies = uneven_pool();
    let dynamic: Vec<usize> = (1..bodies.len()).collect();
    let mut world = sleeping_world(&ctx, &bodies);
    let (asleep, steps) = step_until_asleep(&mut world, &dynamic, SETTLE_STEPS);
    eprintln!("{}-box pool asleep after {steps} steps", dynamic.len());
    // Resting takes TIME_TO_SLEEP at least: an island cannot sleep before 30 steps.
    assert!(
        steps as Real * DT >= TIME_TO_SLEEP,
        "asleep after {steps} steps"
    );
    assert!(!asleep.sleeping[0], "the floor is fixed, it never sleeps");
    for &i in &dynamic {
        // Asleep where it rests: each cube within 5 mm of its layer's height (the soft
        // contacts' slop and the 1 mm start gaps are smaller), and at exactly zero velocity.
        let layer = ((i - 1) / (POOL_SIDE * POOL_SIDE)) as Real;
        let expected = HALF + layer * 2.0 * HALF;
        let y = asleep.pose(i).translation.y;
        assert!(
            (y - expected).abs() < 0.005,
            "body {i}: y {y}, expected {expected}"
        );
        let v = &asleep.velocities[i];
        assert!(
            v.linear.iter().chain(&v.angular).all(|&c| c == 0.0),
            "body {i}: {v:?}"
        );
    }
    // Once asleep, a second of steps changes no bit of any pose.
    for _ in 0..60 {
        world.step().unwrap();
    }
    let later = world.read_now(STATE).unwrap();
    for &i in &dynamic {
        assert!(later.sleeping[i], "body {i} woke up by itself");
        assert!(
            same_bits(&later.poses[i], &asleep.poses[i]),
            "body {i} moved while asleep: {:?} -> {:?}",
            asleep.poses[i],
            later.poses[i]
        );
    }
}

#[test]
fn a_box_dropped_on_one_sleeping_pile_wakes_that_pile_only() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // Two 2 x 2 piles two cubes high, 6 m apart, and a lone cube 6 m away from both.
    let mut bodies = vec![floor()];
    bodies.extend(pile(-3.0, 0.0, 2, 2));
    bodies.extend(pile(3.0, 0.0, 2, 2));
    bodies.push(cube(0.0, 0, 6.0));
    let pile_a: Vec<usize> = (1..9).collect();
    let pile_b: Vec<usize> = (9..17).collect();
    let dropper = 17;
    let dynamic: Vec<usize> = (1..bodies.len()).collect();
    let mut world = sleeping_world(&ctx, &bodies);
    let (asleep, _) = step_until_asleep(&mut world, &dynamic, SETTLE_STEPS);
    // The cube goes 1 m above pile A's top (two cubes: 1 m) and falls at 1 m/s.
    let top = 4.0 * HALF;
    let above = Pose::translation(-3.0, top + 1.0 + HALF, 0.0);
    world.set_pose(dropper, &above).unwrap();
    world
        .set_velocity(dropper, &Vec3::new(0.0, -1.0, 0.0), &Vec3::zeros())
        .unwrap();
    let mut pile_a_woke = false;
    // A 1 m fall at 1 m/s start takes about 0.36 s; a second is ample to land.
    for _ in 0..60 {
        world.step().unwrap();
        let snap = world.read_now(STATE).unwrap();
        pile_a_woke |= pile_a.iter().all(|&i| !snap.sleeping[i]);
        for &i in &pile_b {
            assert!(snap.sleeping[i], "pile B's body {i} woke");
            assert!(
                same_bits(&snap.poses[i], &asleep.poses[i]),
                "pile B's body {i} moved"
            );
        }
    }
    assert!(pile_a_woke, "the dropped cube did not wake pile A");
    // It landed on pile A: its centre one cube above the pile's top, within 5 cm (it may
    // settle on the edge between two columns, slightly tilted).
    let landed = world
        .read_now(STATE)
        .unwrap()
        .pose(dropper)
        .translation
        .vector;
    assert!(
        (landed.y - (top + HALF)).abs() < 0.05,
        "dropper at {landed:?}"
    );
    assert!(
        (landed.x + 3.0).abs() < 0.6 && landed.z.abs() < 0.6,
        "dropper at {landed:?}"
    );
    // Pile A with the cube on it is one island now, and it falls asleep again.
    let island: Vec<usize> = pile_a.iter().copied().chain([dropper]).collect();
    step_until_asleep(&mut world, &island, SETTLE_STEPS);
}

#[test]
fn host_pose_velocity_impulse_and_wake_calls_wake_a_sleeping_island() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // Five two-cube stacks 2 m apart: stack s is bodies 1 + 2s (bottom) and 2 + 2s (top).
    let mut bodies = vec![floor()];
    for s in 0..5 {
        bodies.extend(pile(2.0 * s as Real, 0.0, 1, 2));
    }
    let dynamic: Vec<usize> = (1..bodies.len()).collect();
    let mut world = sleeping_world(&ctx, &bodies);
    let (asleep, _) = step_until_asleep(&mut world, &dynamic, SETTLE_STEPS);
    let top = |s: usize| 2 + 2 * s;
    let bottom = |s: usize| 1 + 2 * s;
    let y0 = |i: usize| asleep.pose(i).translation.y;
    let up = Vec3::new(0.0, 1.0, 0.0);
    // Stack 2: its top cube gets an upward impulse of 1 m/s times its mass, at its centre,
    // queued first: the pose set next submits it at once, and it must still count.
    let mass = 1.0 / bodies[top(2)].inverse_mass;
    let centre = Point3::from(asleep.pose(top(2)).translation.vector);
    world.apply_impulse(top(2), &(up * mass), &centre).unwrap();
    // Stack 0: its top cube is lifted 2 cm.
    let mut lifted = asleep.pose(top(0));
    lifted.translation.y += 0.02;
    world.set_pose(top(0), &lifted).unwrap();
    // Stack 1: its top cube is sent up at 1 m/s.
    world.set_velocity(top(1), &up, &Vec3::zeros()).unwrap();
    // Stack 3: an explicit wake of its bottom cube.
    world.wake_up(bottom(3)).unwrap();
    world.step().unwrap();
    let snap = world.read_now(STATE).unwrap();
    for s in 0..4 {
        for i in [bottom(s), top(s)] {
            assert!(!snap.sleeping[i], "stack {s}: body {i} still asleep");
        }
    }
    for i in [bottom(4), top(4)] {
        assert!(snap.sleeping[i], "stack 4 was not touched: body {i} woke");
        assert!(
            same_bits(&snap.poses[i], &asleep.poses[i]),
            "body {i} moved"
        );
    }
    // The woken cubes moved as dynamic bodies in that very step: at 1 m/s less one step of
    // gravity, a cube rises by about dt (1/60 m); half of that is a safe floor.
    for s in [1, 2] {
        let rise = snap.pose(top(s)).translation.y - y0(top(s));
        assert!(rise > 0.5 * DT, "stack {s}: top rose {rise} m");
    }
    // The lifted cube kept its new pose, less one step of free fall: semi-implicit Euler
    // over any number of substeps drops it between g dt^2 / 2 and g dt^2 (2.7 mm).
    let fall = world.config().gravity.norm() * DT * DT;
    let drop = y0(top(0)) + 0.02 - snap.pose(top(0)).translation.y;
    assert!(
        drop >= 0.5 * fall - 1e-4 && drop <= fall + 1e-4,
        "stack 0: top fell {drop} m in a step ({fall} m at most)"
    );
}

#[test]
fn sleep_on_steps_bit_for_bit_like_sleep_off_until_something_sleeps() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // A pile with a cube falling onto it from 0.5 m, spinning: 20 steps (a third of a
    // second) is less than TIME_TO_SLEEP, so no island can have fallen asleep.
    let mut bodies = vec![floor()];
    bodies.extend(pile(0.0, 0.0, 3, 2));
    bodies.push(body(
        BodyKind::Dynamic,
        Pose::new(Vec3::new(0.1, 1.5, 0.2), Vec3::new(0.3, 0.2, 0.1)),
    ));
    let states = vec![BodyState::default(); bodies.len()];
    let steps = 20;
    assert!((steps as Real) * DT < TIME_TO_SLEEP);
    let run = |sleep: bool| {
        let mut world = GpuWorld::new(&ctx, GpuWorldConfig::default()).unwrap();
        world.set_bodies(&bodies, &states).unwrap();
        set_sleep(&mut world, sleep);
        for _ in 0..steps {
            world.step().unwrap();
        }
        world.read_now(STATE).unwrap()
    };
    let (on, off) = (run(true), run(false));
    assert_eq!(on.sleeping_count(), 0);
    // With sleep off the flags are still answered: every body awake.
    assert_eq!(off.sleeping, vec![false; bodies.len()]);
    // The falling cube moved, so the comparison is not between two still scenes.
    let fell = bodies.last().unwrap().pose.translation.y - on.pose(bodies.len() - 1).translation.y;
    assert!(fell > 0.1, "the cube fell {fell} m");
    for i in 0..bodies.len() {
        assert!(same_bits(&on.poses[i], &off.poses[i]), "body {i} differs");
    }
}

#[test]
fn turning_sleep_off_wakes_every_sleeping_body() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let mut bodies = vec![floor()];
    bodies.extend(pile(0.0, 0.0, 1, 2));
    let mut world = sleeping_world(&ctx, &bodies);
    step_until_asleep(&mut world, &[1, 2], SETTLE_STEPS);
    set_sleep(&mut world, false);
    // Awake again, the top cube answers a velocity as a dynamic body: sent up at 1 m/s it
    // rises by about dt in one step (half of that is a safe floor).
    let before = world.read_now(STATE).unwrap().pose(2).translation.y;
    world
        .set_velocity(2, &Vec3::new(0.0, 1.0, 0.0), &Vec3::zeros())
        .unwrap();
    world.step().unwrap();
    let after = world.read_now(STATE).unwrap();
    assert_eq!(after.sleeping, vec![false; 3]);
    assert!(after.pose(2).translation.y - before > 0.5 * DT);
}

#[test]
fn a_moving_kinematic_box_wakes_the_sleeping_box_it_reaches_and_pushes_it() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // A cube resting at x = 0, and a kinematic slab sliding along +x at 1 m/s from x = -3,
    // 5 cm above the floor: it reaches the cube after about 2.4 s, long after the cube sleeps
    // (at about 0.5 s). The broad phase pairs neither a kinematic body with a sleeping one,
    // so only the kinematic wake can stop the slab from passing through the sleeping cube.
    let pusher_half = Vec3::new(0.25, 0.2, 0.5);
    let pusher = body(BodyKind::Kinematic, Pose::translation(-3.0, 0.25, 0.0));
    let pusher = Body {
        shape: Cuboid::new(pusher_half),
        ..pusher
    };
    let bodies = vec![floor(), cube(0.0, 0, 0.0), pusher];
    let speed = 1.0;
    let mut states = vec![BodyState::default(); 3];
    states[2] = BodyState::moving(Vec3::new(speed, 0.0, 0.0), Vec3::zeros());
    let mut world = GpuWorld::new(&ctx, GpuWorldConfig::default()).unwrap();
    world.set_bodies(&bodies, &states).unwrap();
    set_sleep(&mut world, true);
    let (asleep, steps) = step_until_asleep(&mut world, &[1], SETTLE_STEPS);
    let pusher_x = asleep.pose(2).translation.x;
    // The slab has not reached the cube yet when it sleeps (their faces are 2.25 m apart at
    // the start; the margins and sweeps add centimetres).
    assert!(
        pusher_x + pusher_half.x < -HALF - 0.5,
        "slab at {pusher_x} after {steps} steps"
    );
    // Three more seconds: the slab crosses the cube's starting place.
    let mut woke = false;
    for _ in 0..180 {
        world.step().unwrap();
        woke |= !world.read_now(STATE).unwrap().sleeping[1];
    }
    let end = world.read_now(STATE).unwrap();
    assert!(woke, "the cube never woke");
    // Pushed, the cube stays ahead of the slab: its centre at least its half extent past the
    // slab's face, less 1 cm of contact softness.
    let slab_face = end.pose(2).translation.x + pusher_half.x;
    let x = end.pose(1).translation.x;
    assert!(
        slab_face > HALF,
        "the slab did not get past x = 0: {slab_face}"
    );
    assert!(
        x > slab_face + HALF - 0.01,
        "cube at {x}, slab face at {slab_face}"
    );
}

#[test]
fn sleep_turned_on_before_any_body_is_uploaded_works_and_bad_wakes_are_errors() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let mut world = GpuWorld::new(&ctx, GpuWorldConfig::default()).unwrap();
    let on = Effects {
        sleep: true,
        ..world.effects()
    };
    // On, off and on again with no body uploaded: nothing to wake, nothing to fail on.
    world.set_effects(on).unwrap();
    world.set_effects(Effects { sleep: false, ..on }).unwrap();
    assert!(!world.effects().sleep);
    world.set_effects(on).unwrap();
    world.step().unwrap();
    // A body index past the world is an error naming the field, not a panic.
    let err = world.wake_up(0).unwrap_err().to_string();
    assert!(err.contains("body"), "{err}");
    let bodies = vec![floor(), cube(0.0, 0, 0.0)];
    world
        .set_bodies(&bodies, &[BodyState::default(); 2])
        .unwrap();
    assert!(world.effects().sleep, "an upload keeps sleep on");
    step_until_asleep(&mut world, &[1], SETTLE_STEPS);
    let err = world.wake_up(2).unwrap_err().to_string();
    assert!(err.contains("body") && err.contains('2'), "{err}");
}
