//! Bad input is an `Err` naming the field, and leaves the world exactly as it was.

use tumble::prelude::*;

use crate::stability::world_config;

/// What a call must not change: the body count and every pose and velocity.
#[derive(Debug, PartialEq)]
struct Snapshot {
    count: usize,
    bodies: Vec<(BodyHandle, Pose, Vec3, Vec3)>,
}

fn snapshot(world: &World) -> Snapshot {
    Snapshot {
        count: world.body_count(),
        bodies: world
            .handles()
            .iter()
            .map(|&h| {
                (
                    h,
                    world.pose(h).unwrap(),
                    world.linear_velocity(h).unwrap(),
                    world.angular_velocity(h).unwrap(),
                )
            })
            .collect(),
    }
}

/// Asserts `result` is an `InvalidValue` error naming `field`.
fn expect_field<T: std::fmt::Debug>(result: Result<T, Error>, field: &str) {
    match result {
        Err(Error::InvalidValue { field: f, .. }) => assert_eq!(f, field),
        other => panic!("expected an error naming {field}, got {other:?}"),
    }
}

/// A small world with a floor, a resting cube and a kinematic box, stepped a few times.
fn small_world(backend: Backend, solver: SolverConfig) -> (World, BodyHandle) {
    let mut world = World::new(world_config(backend, solver)).unwrap();
    world
        .add_body(
            BodyDesc::fixed()
                .cuboid(Vec3::new(5.0, 0.5, 5.0))
                .translation(0.0, -0.5, 0.0),
        )
        .unwrap();
    let cube = world
        .add_body(BodyDesc::dynamic().translation(0.0, 0.5, 0.0))
        .unwrap();
    world
        .add_body(
            BodyDesc::kinematic()
                .translation(3.0, 0.5, 0.0)
                .linear_velocity(Vec3::new(0.1, 0.0, 0.0)),
        )
        .unwrap();
    for _ in 0..5 {
        world.step().unwrap();
    }
    (world, cube)
}

/// Every bad field of a body descriptor is rejected by name and adds nothing.
pub fn bad_bodies_are_rejected(backend: Backend, solver: SolverConfig) {
    let (mut world, _) = small_world(backend, solver);
    let before = snapshot(&world);
    let nan = Real::NAN;
    let inf = Real::INFINITY;
    let ok = BodyDesc::dynamic().translation(0.0, 3.0, 0.0);
    let cases: Vec<(BodyDesc, &str)> = vec![
        (ok.cuboid(Vec3::new(-0.5, 0.5, 0.5)), "half_extents.x"),
        (ok.cuboid(Vec3::new(0.5, 0.0, 0.5)), "half_extents.y"),
        (ok.cuboid(Vec3::new(0.5, 0.5, nan)), "half_extents.z"),
        (ok.cuboid(Vec3::new(inf, 0.5, 0.5)), "half_extents.x"),
        (ok.density(-1.0), "density"),
        (ok.density(0.0), "density"),
        (ok.density(nan), "density"),
        (ok.density(inf), "density"),
        (BodyDesc::fixed().density(nan), "density"),
        (ok.friction(-0.1), "friction"),
        (ok.friction(nan), "friction"),
        (ok.restitution(1.5), "restitution"),
        (ok.restitution(-0.5), "restitution"),
        (
            ok.linear_velocity(Vec3::new(0.0, nan, 0.0)),
            "linear_velocity",
        ),
        (
            ok.angular_velocity(Vec3::new(inf, 0.0, 0.0)),
            "angular_velocity",
        ),
        (ok.translation(nan, 0.0, 0.0), "pose"),
        (ok.linear_damping(-1.0), "linear_damping"),
        (ok.angular_damping(nan), "angular_damping"),
    ];
    for (desc, field) in cases {
        expect_field(world.add_body(desc), field);
        assert_eq!(
            snapshot(&world),
            before,
            "adding a bad {field} changed the world"
        );
    }
}

/// Bad setter arguments are rejected by name and change nothing.
pub fn bad_updates_are_rejected(backend: Backend, solver: SolverConfig) {
    let (mut world, cube) = small_world(backend, solver);
    let before = snapshot(&world);
    let nan = Real::NAN;
    expect_field(
        world.set_pose(cube, Pose::translation(0.0, nan, 0.0)),
        "pose",
    );
    expect_field(
        world.set_linear_velocity(cube, Vec3::new(nan, 0.0, 0.0)),
        "linear_velocity",
    );
    expect_field(
        world.set_angular_velocity(cube, Vec3::new(0.0, 0.0, Real::INFINITY)),
        "angular_velocity",
    );
    expect_field(
        world.apply_impulse(cube, Vec3::new(nan, 0.0, 0.0), Point3::origin()),
        "impulse",
    );
    expect_field(
        world.apply_impulse(cube, Vec3::x(), Point3::new(0.0, nan, 0.0)),
        "point",
    );
    let floor = world.handles()[0];
    expect_field(
        world.set_linear_velocity(floor, Vec3::x()),
        "linear_velocity",
    );
    assert_eq!(snapshot(&world), before);
}

/// Removed handles and handles this world never issued are errors everywhere.
pub fn stale_handles_are_rejected(backend: Backend, solver: SolverConfig) {
    let (mut world, cube) = small_world(backend, solver);
    let doomed = world
        .add_body(BodyDesc::dynamic().translation(5.0, 0.5, 0.0))
        .unwrap();
    world.remove_body(doomed).unwrap();
    // A handle from a bigger world: its slot does not exist here.
    let mut other = World::new(world_config(backend, solver)).unwrap();
    let mut foreign = None;
    for i in 0..10 {
        foreign = Some(
            other
                .add_body(BodyDesc::dynamic().translation(2.0 * i as Real, 0.5, 0.0))
                .unwrap(),
        );
    }
    let foreign = foreign.unwrap();
    let before = snapshot(&world);
    for (h, removed) in [(doomed, true), (foreign, false)] {
        let check = |r: Result<(), Error>| match r {
            Err(Error::RemovedHandle(x)) if removed => assert_eq!(x, h),
            Err(Error::UnknownHandle(x)) if !removed => assert_eq!(x, h),
            other => panic!("{h:?}: expected a handle error, got {other:?}"),
        };
        check(world.pose(h).map(|_| ()));
        check(world.linear_velocity(h).map(|_| ()));
        check(world.angular_velocity(h).map(|_| ()));
        check(world.set_pose(h, Pose::identity()));
        check(world.set_linear_velocity(h, Vec3::zeros()));
        check(world.set_angular_velocity(h, Vec3::zeros()));
        check(world.apply_impulse(h, Vec3::x(), Point3::origin()));
        check(world.remove_body(h));
        assert_eq!(snapshot(&world), before);
    }
    // The survivors are untouched and still step.
    assert!(world.contains(cube));
    world.step().unwrap();
}

/// Bad world settings are rejected by name.
pub fn bad_configs_are_rejected(backend: Backend, solver: SolverConfig) {
    let good = world_config(backend, solver);
    let nan = Real::NAN;
    let cases: Vec<(WorldConfig, &str)> = vec![
        (WorldConfig { dt: 0.0, ..good }, "dt"),
        (
            WorldConfig {
                dt: -1.0 / 60.0,
                ..good
            },
            "dt",
        ),
        (WorldConfig { dt: nan, ..good }, "dt"),
        (
            WorldConfig {
                gravity: Vec3::new(0.0, nan, 0.0),
                ..good
            },
            "gravity",
        ),
        (
            WorldConfig {
                gravity: Vec3::new(Real::INFINITY, 0.0, 0.0),
                ..good
            },
            "gravity",
        ),
        (
            WorldConfig {
                margin: -0.01,
                ..good
            },
            "margin",
        ),
        (
            WorldConfig {
                solver: SolverConfig {
                    iterations: 0,
                    ..solver
                },
                ..good
            },
            "solver.iterations",
        ),
        (
            WorldConfig {
                solver: SolverConfig {
                    substeps: 0,
                    ..solver
                },
                ..good
            },
            "solver.substeps",
        ),
        (
            WorldConfig {
                solver: SolverConfig {
                    contact_hertz: -30.0,
                    ..solver
                },
                ..good
            },
            "solver.contact_hertz",
        ),
        (
            WorldConfig {
                solver: SolverConfig {
                    damping_ratio: nan,
                    ..solver
                },
                ..good
            },
            "solver.damping_ratio",
        ),
        (
            WorldConfig {
                solver: SolverConfig {
                    max_push_out: 0.0,
                    ..solver
                },
                ..good
            },
            "solver.max_push_out",
        ),
        (
            WorldConfig {
                solver: SolverConfig {
                    baumgarte: 2.0,
                    ..solver
                },
                ..good
            },
            "solver.baumgarte",
        ),
        (
            WorldConfig {
                solver: SolverConfig {
                    slop: -0.1,
                    ..solver
                },
                ..good
            },
            "solver.slop",
        ),
    ];
    for (config, field) in cases {
        expect_field(World::new(config), field);
    }
}
