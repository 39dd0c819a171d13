//! The queries' contracts: they see the poses of the last step and of every edit, filters
//! leave out what they name, and bad input is an error naming the argument.

use tumble::QueryFilter;
use tumble_tests::bad_input::{expect_field, snapshot};

use super::*;

/// A floor (top face at y = 0) and a row of cubes dropped from different heights.
fn dropping_row() -> (World, BodyHandle, Vec<BodyHandle>) {
    let config = WorldConfig {
        backend: Backend::Cpu,
        ..Default::default()
    };
    let mut world = World::new(config).unwrap();
    let floor = world
        .add_body(
            BodyDesc::fixed()
                .cuboid(Vec3::new(20.0, 0.5, 5.0))
                .translation(0.0, -0.5, 0.0),
        )
        .unwrap();
    let cubes = (0..8)
        .map(|i| {
            let x = -14.0 + 4.0 * i as Real;
            world
                .add_body(BodyDesc::dynamic().translation(x, 1.0 + 0.5 * i as Real, 0.0))
                .unwrap()
        })
        .collect();
    (world, floor, cubes)
}

/// After each of 90 CPU steps, a ray down onto each cube hits its top face where the stepped
/// pose puts it, a point just inside the cube finds it, and a box cast down finds its top.
#[test]
fn queries_on_a_cpu_world_see_the_stepped_poses() {
    let (mut world, floor, cubes) = dropping_row();
    let f = QueryFilter::default();
    let start: Vec<Pose> = cubes.iter().map(|&c| world.pose(c).unwrap()).collect();
    for step in 0..90 {
        world.step().unwrap();
        for &c in &cubes {
            let pose = world.pose(c).unwrap();
            let centre = Point3::from(pose.translation.vector);
            let above = centre + Vec3::new(0.0, 5.0, 0.0);
            let hit = world.cast_ray(above, -Vec3::y(), 10.0, f).unwrap().unwrap();
            assert_eq!(hit.body, c, "step {step}");
            // The cube turns little as it falls straight, so its top is near centre + 0.5.
            let top = Cuboid::new(Vec3::repeat(0.5))
                .cast_ray(&pose, &above, &-Vec3::y(), 10.0)
                .unwrap();
            assert!(
                (hit.toi - top.toi).abs() < 1e-5,
                "step {step}: {hit:?} vs {top:?}"
            );
            assert_eq!(world.bodies_containing_point(centre, f).unwrap(), vec![c]);
            let cast = world
                .cast_box(
                    Vec3::repeat(0.1),
                    Pose::translation(above.x, above.y, above.z),
                    -Vec3::y(),
                    10.0,
                    f,
                )
                .unwrap()
                .unwrap();
            assert_eq!(cast.body, c);
            assert!((cast.toi - (top.toi - 0.1)).abs() < 1e-4, "{cast:?}");
        }
    }
    // The cubes fell and rest on the floor: their tops are at 1 m, not where they started.
    for (&c, s) in cubes.iter().zip(&start) {
        let x = s.translation.vector.x;
        let hit = world
            .cast_ray(Point3::new(x, 10.0, 0.0), -Vec3::y(), 20.0, f)
            .unwrap()
            .unwrap();
        assert_eq!(hit.body, c);
        assert!((hit.point.y - 1.0).abs() < 0.02, "{hit:?}");
    }
    // Between the cubes the floor.
    let hit = world
        .cast_ray(Point3::new(-12.0, 10.0, 0.0), -Vec3::y(), 20.0, f)
        .unwrap()
        .unwrap();
    assert_eq!(hit.body, floor);
}

/// Moving, adding and removing a body are seen by the next query (the query tree is rebuilt).
#[test]
fn queries_see_edits_between_steps() {
    let (mut world, floor, cubes) = dropping_row();
    let f = QueryFilter::default();
    let probe = |world: &World| {
        world
            .cast_ray(Point3::new(0.0, 10.0, 0.0), -Vec3::y(), 20.0, f)
            .unwrap()
            .map(|h| h.body)
    };
    assert_eq!(probe(&world), Some(floor));
    world
        .set_pose(cubes[0], Pose::translation(0.0, 3.0, 0.0))
        .unwrap();
    assert_eq!(probe(&world), Some(cubes[0]));
    let extra = world
        .add_body(BodyDesc::fixed().translation(0.0, 6.0, 0.0))
        .unwrap();
    assert_eq!(probe(&world), Some(extra));
    world.remove_body(extra).unwrap();
    assert_eq!(probe(&world), Some(cubes[0]));
    world.remove_body(cubes[0]).unwrap();
    assert_eq!(probe(&world), Some(floor));
}

/// Each filter leaves out what it names and nothing else.
#[test]
fn filters_leave_out_what_they_name() {
    let (mut world, floor, cubes) = dropping_row();
    // A stack: cube 0 above the floor at x = 0, a second body above it.
    world
        .set_pose(cubes[0], Pose::translation(0.0, 0.5, 0.0))
        .unwrap();
    world
        .set_pose(cubes[1], Pose::translation(0.0, 2.0, 0.0))
        .unwrap();
    let down = |world: &World, f: QueryFilter<'_>| {
        world
            .cast_ray_all(Point3::new(0.0, 10.0, 0.0), -Vec3::y(), 20.0, f)
            .unwrap()
            .iter()
            .map(|h| h.body)
            .collect::<Vec<_>>()
    };
    assert_eq!(
        down(&world, QueryFilter::new()),
        vec![cubes[1], cubes[0], floor]
    );
    let f = QueryFilter::new().exclude(cubes[1]);
    assert_eq!(down(&world, f), vec![cubes[0], floor]);
    assert_eq!(
        down(&world, QueryFilter::new().skip_fixed()),
        vec![cubes[1], cubes[0]]
    );
    let not_zero = |h: BodyHandle| h != cubes[0];
    let f = QueryFilter::new().predicate(&not_zero);
    assert_eq!(down(&world, f), vec![cubes[1], floor]);
    // The closest hit honours the same filter.
    let f = QueryFilter::new().exclude(cubes[1]).skip_fixed();
    let hit = world
        .cast_ray(Point3::new(0.0, 10.0, 0.0), -Vec3::y(), 20.0, f)
        .unwrap();
    assert_eq!(hit.map(|h| h.body), Some(cubes[0]));
}

/// With sleep on, a resting cube falls asleep; `skip_sleeping` then sees through it.
#[test]
fn skip_sleeping_sees_through_sleeping_bodies() {
    let mut config = WorldConfig {
        backend: Backend::Cpu,
        ..Default::default()
    };
    config.effects.sleep = tumble::EffectSwitch::On;
    let mut world = World::new(config).unwrap();
    let cube = tumble_tests::bad_input::floor_and_cube(&mut world);
    let floor = world.handles()[0];
    let from = Point3::new(0.0, 10.0, 0.0);
    let first = |world: &World, f: QueryFilter<'_>| {
        world
            .cast_ray(from, -Vec3::y(), 20.0, f)
            .unwrap()
            .map(|h| h.body)
    };
    let skip = QueryFilter::new().skip_sleeping();
    assert_eq!(first(&world, skip), Some(cube), "awake at the start");
    for _ in 0..600 {
        if world.is_sleeping(cube).unwrap() {
            break;
        }
        world.step().unwrap();
    }
    assert!(
        world.is_sleeping(cube).unwrap(),
        "the resting cube sleeps within 10 s"
    );
    assert_eq!(first(&world, QueryFilter::new()), Some(cube));
    // The floor is fixed, never asleep.
    assert_eq!(first(&world, skip), Some(floor));
    world.wake_up(cube).unwrap();
    assert_eq!(first(&world, skip), Some(cube), "awake again");
}

/// Every bad argument is an `InvalidValue` naming it, and leaves the world as it was; junk
/// input never panics.
#[test]
fn bad_query_input_is_an_error_naming_the_argument() {
    let (mut world, _, _) = dropping_row();
    world.step().unwrap();
    let before = snapshot(&world);
    let f = QueryFilter::default();
    let o = Point3::new(0.0, 5.0, 0.0);
    let (nan, inf) = (Real::NAN, Real::INFINITY);
    let down = -Vec3::y();
    expect_field(
        world.cast_ray(Point3::new(nan, 0.0, 0.0), down, 1.0, f),
        "origin",
    );
    expect_field(
        world.cast_ray(Point3::new(0.0, inf, 0.0), down, 1.0, f),
        "origin",
    );
    expect_field(
        world.cast_ray(Point3::new(1e6, 0.0, 0.0), down, 1.0, f),
        "origin",
    );
    expect_field(world.cast_ray(o, Vec3::zeros(), 1.0, f), "dir");
    expect_field(world.cast_ray(o, Vec3::new(0.0, nan, 0.0), 1.0, f), "dir");
    expect_field(world.cast_ray(o, Vec3::new(inf, 0.0, 0.0), 1.0, f), "dir");
    expect_field(world.cast_ray(o, down, -1.0, f), "max_toi");
    expect_field(world.cast_ray(o, down, nan, f), "max_toi");
    expect_field(world.cast_ray_all(o, Vec3::zeros(), 1.0, f), "dir");
    expect_field(world.cast_ray_all(o, down, -0.5, f), "max_toi");
    let h = Vec3::repeat(0.5);
    let at = Pose::translation(0.0, 5.0, 0.0);
    expect_field(
        world.cast_box(Vec3::new(0.0, 1.0, 1.0), at, down, 1.0, f),
        "half_extents.x",
    );
    expect_field(
        world.cast_box(Vec3::new(1.0, -1.0, 1.0), at, down, 1.0, f),
        "half_extents.y",
    );
    expect_field(
        world.cast_box(Vec3::new(1.0, 1.0, nan), at, down, 1.0, f),
        "half_extents.z",
    );
    expect_field(
        world.cast_box(Vec3::new(1.0, 1.0, inf), at, down, 1.0, f),
        "half_extents.z",
    );
    let mut bad_pose = at;
    bad_pose.translation.vector.x = nan;
    expect_field(world.cast_box(h, bad_pose, down, 1.0, f), "pose");
    expect_field(world.cast_box(h, at, Vec3::zeros(), 1.0, f), "velocity");
    expect_field(
        world.cast_box(h, at, Vec3::new(nan, 0.0, 0.0), 1.0, f),
        "velocity",
    );
    expect_field(world.cast_box(h, at, down, -1.0, f), "max_toi");
    let flipped = Aabb::new(Point3::new(1.0, 0.0, 0.0), Point3::new(0.0, 1.0, 1.0));
    expect_field(world.bodies_in_aabb(flipped, f), "aabb");
    let open = Aabb::new(Point3::new(-inf, 0.0, 0.0), Point3::new(0.0, 1.0, 1.0));
    expect_field(world.bodies_in_aabb(open, f), "aabb");
    expect_field(
        world.bodies_containing_point(Point3::new(nan, 0.0, 0.0), f),
        "point",
    );
    expect_field(
        world.project_point(Point3::new(0.0, 0.0, inf), 1.0, f),
        "point",
    );
    expect_field(world.project_point(o, -1.0, f), "max_dist");
    expect_field(world.project_point(o, nan, f), "max_dist");
    // The message names the value.
    let e = world.cast_ray(o, Vec3::zeros(), 1.0, f).unwrap_err();
    assert!(
        e.to_string().contains("dir") && e.to_string().contains("0.0"),
        "{e}"
    );
    assert_eq!(snapshot(&world), before);
    // Junk of every kind: an answer or an error, never a panic.
    let junk = [
        0.0, -0.0, 1e-40, 1e-30, 1.0, -3.0, 1e6, 3e38, nan, inf, -inf,
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for _ in 0..2000 {
        let mut pick = || junk[rng.random_range(0..junk.len())];
        let v = Vec3::new(pick(), pick(), pick());
        let p = Point3::new(pick(), pick(), pick());
        let t = pick();
        let _ = world.cast_ray(p, v, t, f);
        let _ = world.cast_ray_all(p, v, t, f);
        let _ = world.cast_box(v, Pose::translation(p.x, p.y, p.z), v, t, f);
        let _ = world.bodies_in_aabb(Aabb::new(p, p + v), f);
        let _ = world.bodies_containing_point(p, f);
        let _ = world.project_point(p, t, f);
    }
    assert_eq!(snapshot(&world), before);
}
