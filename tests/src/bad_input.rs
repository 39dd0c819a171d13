//! Bad input is an `Err` naming the field, and leaves the world exactly as it was.

use tumble::prelude::*;

use crate::facade::{add_floor, cube_at};
use crate::stability::world_config;

/// What a call must not change: the step count, the body count, and every pose and
/// velocity bit for bit (`-0.0` differs from `0.0`, a NaN from every number), with a hash of
/// those bits for the messages.
#[derive(Debug, PartialEq)]
pub struct Snapshot {
    steps: u64,
    count: usize,
    bodies: Vec<(BodyHandle, [u32; 13])>,
    hash: u64,
}

/// Body `h`'s translation, rotation (quaternion `x, y, z, w`), linear and angular velocity,
/// by component.
pub fn body_state(world: &World, h: BodyHandle) -> [Real; 13] {
    let p = world.pose(h).unwrap();
    let v = world.linear_velocity(h).unwrap();
    let w = world.angular_velocity(h).unwrap();
    let t = p.translation.vector;
    let q = p.rotation.coords;
    [
        t.x, t.y, t.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, w.x, w.y, w.z,
    ]
}

/// The bits of a world's state now (see [`Snapshot`]).
pub fn snapshot(world: &World) -> Snapshot {
    let bodies: Vec<(BodyHandle, [u32; 13])> = world
        .handles()
        .iter()
        .map(|&h| (h, body_state(world, h).map(f32::to_bits)))
        .collect();
    // FNV-1a over every bit above.
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    for (h, bits) in &bodies {
        for word in std::iter::once(h.to_bits()).chain(bits.iter().map(|&b| u64::from(b))) {
            hash = (hash ^ word).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    Snapshot {
        steps: world.step_count(),
        count: world.body_count(),
        bodies,
        hash,
    }
}

/// Asserts `result` is an `InvalidValue` error naming `field`.
pub fn expect_field<T: std::fmt::Debug>(result: Result<T, Error>, field: &str) {
    match result {
        Err(Error::InvalidValue { field: f, .. }) => assert_eq!(f, field),
        other => panic!("expected an error naming {field}, got {other:?}"),
    }
}

/// Adds a 10 m square floor slab (top face at y = 0) and a unit cube resting on it; returns
/// the cube.
pub fn floor_and_cube(world: &mut World) -> BodyHandle {
    add_floor(world, 5.0);
    cube_at(world, 0.0, 0.5, 0.0)
}

/// A small world with a floor, a resting cube and a kinematic box, stepped a few times.
pub fn small_world(backend: Backend, solver: SolverConfig) -> (World, BodyHandle) {
    let mut world = World::new(world_config(backend, solver)).unwrap();
    let cube = floor_and_cube(&mut world);
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
        // Finite but outside the bounds of tumble_solver::bounds (docs/errors.md).
        (ok.cuboid(Vec3::new(1e-4, 0.5, 0.5)), "half_extents.x"),
        (ok.cuboid(Vec3::new(0.5, 1e-40, 0.5)), "half_extents.y"),
        (ok.cuboid(Vec3::new(0.5, 0.5, 2e3)), "half_extents.z"),
        (ok.cuboid(Vec3::new(1e30, 0.5, 0.5)), "half_extents.x"),
        (ok.density(1e-30), "density"),
        (ok.density(2e5), "density"),
        (ok.density(1e30), "density"),
        (BodyDesc::fixed().density(1e-40), "density"),
        (ok.friction(1e30), "friction"),
        (ok.friction(10.5), "friction"),
        (
            ok.linear_velocity(Vec3::new(0.0, 0.0, 400.5)),
            "linear_velocity",
        ),
        (
            ok.linear_velocity(Vec3::new(1e30, 0.0, 0.0)),
            "linear_velocity",
        ),
        (
            // Above the spin every allowed world carries at 1/60 s: pi/4 * 64 * 60 = 3016.
            ok.angular_velocity(Vec3::new(0.0, 4e3, 0.0)),
            "angular_velocity",
        ),
        (
            ok.angular_velocity(Vec3::new(1e30, 1e30, 1e30)),
            "angular_velocity",
        ),
        (ok.translation(1e6, 0.0, 0.0), "pose"),
        (ok.translation(0.0, -40_000.0, 0.0), "pose"),
        (ok.translation(30_000.0, 0.0, 30_000.0), "pose"),
        (ok.pose(zero_rotation()), "pose"),
        (ok.linear_damping(1e30), "linear_damping"),
        (ok.angular_damping(2e4), "angular_damping"),
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

/// A pose whose rotation is the zero quaternion, which cannot be normalized.
fn zero_rotation() -> Pose {
    let mut pose = Pose::translation(0.0, 3.0, 0.0);
    pose.rotation = Rot::new_unchecked(tumble::nalgebra::Quaternion::new(0.0, 0.0, 0.0, 0.0));
    pose
}

/// Setter arguments that are finite but outside the bounds are rejected by name, and each
/// leaves every pose and velocity bit as it was.
pub fn out_of_bound_updates_are_rejected(backend: Backend, solver: SolverConfig) {
    let (mut world, cube) = small_world(backend, solver);
    let kinematic = world.handles()[2];
    let far = Pose::translation(1e6, 0.0, 0.0);
    let tiny = Pose::translation(0.0, 0.5, 0.0);
    let mut tiny_rotation = tiny;
    tiny_rotation.rotation =
        Rot::new_unchecked(tumble::nalgebra::Quaternion::new(1e-30, 0.0, 0.0, 0.0));
    // Each call is made and checked on its own, the world compared with its state just before.
    type Call = Box<dyn Fn(&mut World) -> Result<(), Error>>;
    fn call(f: impl Fn(&mut World) -> Result<(), Error> + 'static) -> Call {
        Box::new(f)
    }
    let spin_impulse = if solver.substeps <= 6 { "impulse" } else { "" };
    let cases: Vec<(Call, &str)> = vec![
        (call(move |w| w.set_pose(cube, far)), "pose"),
        (
            call(move |w| w.set_pose(cube, Pose::translation(0.0, 32_769.0, 0.0))),
            "pose",
        ),
        (call(move |w| w.set_pose(cube, zero_rotation())), "pose"),
        (call(move |w| w.set_pose(cube, tiny_rotation)), "pose"),
        (
            call(move |w| w.set_linear_velocity(cube, Vec3::new(1e30, 0.0, 0.0))),
            "linear_velocity",
        ),
        (
            call(move |w| w.set_linear_velocity(cube, Vec3::new(300.0, 300.0, 0.0))),
            "linear_velocity",
        ),
        (
            call(move |w| w.set_angular_velocity(cube, Vec3::new(0.0, 1e30, 0.0))),
            "angular_velocity",
        ),
        (
            call(move |w| w.set_angular_velocity(cube, Vec3::new(0.0, 4e3, 0.0))),
            "angular_velocity",
        ),
        (
            call(move |w| {
                w.apply_impulse(cube, Vec3::new(0.0, 1e30, 0.0), Point3::new(0.0, 0.5, 0.0))
            }),
            "impulse",
        ),
        // The 1 kg cube would leave at 1000 m/s, above MAX_SPEED.
        (
            call(move |w| {
                w.apply_impulse(cube, Vec3::new(1e3, 0.0, 0.0), Point3::new(0.0, 0.5, 0.0))
            }),
            "impulse",
        ),
        // 100 N s at 0.5 m from the centre of the 1 kg cube (I = 1/6 kg m^2) leaves it at
        // 100 m/s but spinning at 50 * 6 = 300 rad/s, above what 1/60 s in up to 6 substeps
        // carries (pi/4 * 360 = 283 rad/s).
        (
            call(move |w| {
                w.apply_impulse(cube, Vec3::new(0.0, 0.0, 100.0), Point3::new(0.5, 0.5, 0.0))
            }),
            spin_impulse,
        ),
        (
            call(move |w| w.apply_impulse(cube, Vec3::x(), Point3::new(1e6, 0.0, 0.0))),
            "point",
        ),
        (
            call(move |w| w.set_kinematic_target(kinematic, far)),
            "pose",
        ),
        // 100 m in one 1/60 s step is 6000 m/s.
        (
            call(move |w| w.set_kinematic_target(kinematic, Pose::translation(103.0, 0.5, 0.0))),
            "target",
        ),
        (
            call(move |w| w.set_kinematic_target(kinematic, zero_rotation())),
            "pose",
        ),
        (call(move |w| w.set_kinematic_target(cube, tiny)), "kind"),
    ];
    for (i, (call, field)) in cases.iter().enumerate() {
        let before = snapshot(&world);
        let result = call(&mut world);
        if field.is_empty() {
            // Accepted with this many substeps: the next case starts from its result.
            assert!(
                result.is_ok(),
                "case {i} is within bounds at this substep count and was refused: {result:?}"
            );
            continue;
        }
        expect_field(result, field);
        assert_eq!(
            snapshot(&world),
            before,
            "rejected case {i} ({field}) changed the world"
        );
    }
}

/// Removed handles and handles this world never issued are errors everywhere.
pub fn stale_handles_are_rejected(backend: Backend, solver: SolverConfig) {
    let (mut world, cube) = small_world(backend, solver);
    let doomed = cube_at(&mut world, 5.0, 0.5, 0.0);
    world.remove_body(doomed).unwrap();
    // A handle from a bigger world: its slot does not exist here.
    let mut other = World::new(world_config(backend, solver)).unwrap();
    let mut foreign = None;
    for i in 0..10 {
        foreign = Some(cube_at(&mut other, 2.0 * i as Real, 0.5, 0.0));
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
        // The handle is checked before the pose and the body's kind: a stale handle is named
        // as such even with a valid target, never reported as "not a kinematic body".
        check(world.set_kinematic_target(h, Pose::identity()));
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
        // Friction in the relax passes only with no relax pass would solve no friction.
        (
            WorldConfig {
                solver: SolverConfig {
                    friction_passes: FrictionPasses::RelaxOnly,
                    relax_iterations: 0,
                    ..solver
                },
                ..good
            },
            "solver.friction_passes",
        ),
    ];
    for (config, field) in cases {
        expect_field(World::new(config), field);
    }
    // Finite but outside the bounds of tumble_solver::bounds (docs/errors.md).
    let with_solver = |s: SolverConfig| WorldConfig { solver: s, ..good };
    let cases: Vec<(WorldConfig, &str)> = vec![
        (WorldConfig { dt: 1e-30, ..good }, "dt"),
        (WorldConfig { dt: 1e-5, ..good }, "dt"),
        (WorldConfig { dt: 1.0, ..good }, "dt"),
        (
            WorldConfig {
                gravity: Vec3::new(0.0, -1e30, 0.0),
                ..good
            },
            "gravity",
        ),
        (
            WorldConfig {
                gravity: Vec3::new(800.0, -800.0, 0.0),
                ..good
            },
            "gravity",
        ),
        (
            WorldConfig {
                margin: 1e30,
                ..good
            },
            "margin",
        ),
        (
            WorldConfig {
                margin: 1.5,
                ..good
            },
            "margin",
        ),
        (
            with_solver(SolverConfig {
                substeps: 65,
                ..solver
            }),
            "solver.substeps",
        ),
        (
            with_solver(SolverConfig {
                iterations: 100_000,
                ..solver
            }),
            "solver.iterations",
        ),
        (
            with_solver(SolverConfig {
                relax_iterations: 5000,
                ..solver
            }),
            "solver.relax_iterations",
        ),
        (
            with_solver(SolverConfig {
                contact_hertz: 1e30,
                ..solver
            }),
            "solver.contact_hertz",
        ),
        (
            with_solver(SolverConfig {
                damping_ratio: 1e30,
                ..solver
            }),
            "solver.damping_ratio",
        ),
        (
            with_solver(SolverConfig {
                max_push_out: 1e30,
                ..solver
            }),
            "solver.max_push_out",
        ),
        (
            with_solver(SolverConfig {
                slop: 1e30,
                ..solver
            }),
            "solver.slop",
        ),
        (
            with_solver(SolverConfig {
                restitution_threshold: 1e30,
                ..solver
            }),
            "solver.restitution_threshold",
        ),
    ];
    for (config, field) in cases {
        expect_field(World::new(config), field);
    }
}
