//! `World::cast_rays_gpu`: a batch of rays cast on the GPU in one dispatch, against the GPU
//! world's own buffers, compared ray by ray with the CPU's `World::cast_ray` on the same world
//! (the CPU query reads the same stepped poses back), and its contracts.
//!
//! Needs a GPU (or lavapipe): without one the tests print "skipped: no GPU adapter" and pass,
//! unless `TUMBLE_REQUIRE_GPU=1`. One scene of 66 boxes, three steps, 4,400 rays: a few
//! hundred thousand box tests, well under a second on lavapipe.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble::gpu::GpuContext;
use tumble::prelude::*;
use tumble::{QueryFilter, Ray};
use tumble_tests::bad_input::expect_field;

/// Spacing of the scene's grid, m, and the largest half extent: a box's corner lies within
/// `0.7 * sqrt(3) = 1.21` m of its centre, so jittered by 2 cm two neighbours start apart.
const SPACING: Real = 2.5;
const MAX_HALF: Real = 0.7;

/// A random unit rotation.
fn random_rotation(rng: &mut ChaCha8Rng) -> Rot {
    loop {
        let q = nalgebra::Quaternion::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let n = q.norm();
        if n > 0.1 && n <= 1.0 {
            return Rot::new_normalize(q);
        }
    }
}

/// A random direction of length 0.5 to 2 (the time of impact is in its units); one in ten
/// along a world axis, so that the slab test's parallel case (a zero component) is taken.
fn random_dir(rng: &mut ChaCha8Rng) -> Vec3 {
    let length = rng.random_range(0.5..2.0);
    if rng.random_bool(0.1) {
        let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
        return Vec3::ith(rng.random_range(0..3), sign * length);
    }
    loop {
        let v = Vec3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        let n = v.norm();
        if n > 0.1 && n <= 1.0 {
            return v * (length / n);
        }
    }
}

/// A 4 x 4 x 4 grid of rotated boxes of random sizes (half extents 5 cm to 0.7 m), half of
/// them fixed, the dynamic ones spinning and moving at up to 1 m/s and 2 rad/s under gravity,
/// plus two fixed boxes at one pose (so rays hit both at the same time), on `backend`,
/// stepped three times: the GPU step's own poses, not the uploaded ones.
fn random_world(backend: Backend, seed: u64) -> World {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut world = World::new(WorldConfig {
        backend,
        ..Default::default()
    })
    .expect("world");
    for i in 0..64 {
        let cell = Vec3::new((i % 4) as Real, ((i / 4) % 4) as Real, (i / 16) as Real);
        let jitter = Vec3::from_fn(|_, _| rng.random_range(-0.02..0.02));
        let centre = (cell - Vec3::repeat(1.5)) * SPACING + jitter;
        let half = Vec3::from_fn(|_, _| rng.random_range(0.05f32.ln()..MAX_HALF.ln()).exp());
        let pose = Pose::from_parts(centre.into(), random_rotation(&mut rng));
        let desc = if rng.random_bool(0.5) {
            BodyDesc::fixed()
        } else {
            BodyDesc::dynamic()
                .linear_velocity(Vec3::from_fn(|_, _| rng.random_range(-0.6..0.6)))
                .angular_velocity(Vec3::from_fn(|_, _| rng.random_range(-1.1..1.1)))
        };
        world.add_body(desc.cuboid(half).pose(pose)).expect("body");
    }
    // Two fixed boxes at one pose, outside the grid: every ray into them hits both at the
    // same time, and the CPU answers the first added.
    let twin = Pose::from_parts(Vec3::new(0.0, 0.0, 7.0).into(), random_rotation(&mut rng));
    for _ in 0..2 {
        let desc = BodyDesc::fixed()
            .cuboid(Vec3::new(0.8, 0.5, 0.3))
            .pose(twin);
        world.add_body(desc).expect("twin");
    }
    for _ in 0..3 {
        world.step().expect("step");
    }
    world
}

/// 3,000 rays from random points of a 14 m cube around the grid in random directions (most
/// miss the sparse grid), and 1,400 aimed at a random body's centre from up to 6 m away
/// (hits, some starting inside).
fn random_rays(world: &World, seed: u64) -> Vec<Ray> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut rays: Vec<Ray> = (0..3000)
        .map(|_| {
            let origin = Point3::from(Vec3::from_fn(|_, _| rng.random_range(-7.0..7.0)));
            Ray::new(origin, random_dir(&mut rng))
        })
        .collect();
    let handles = world.handles();
    for _ in 0..1400 {
        let h = handles[rng.random_range(0..handles.len())];
        let target = Point3::from(world.pose(h).unwrap().translation.vector);
        let dir = random_dir(&mut rng);
        let origin = target - dir * rng.random_range(0.0..6.0 / dir.norm());
        rays.push(Ray::new(origin, dir));
    }
    rays
}

/// The GPU batch gives, for every ray, the CPU ray cast's body (or the CPU's miss), its time
/// of impact and its normal. Poses and half extents are the same `f32`s on both sides (the
/// CPU query reads the GPU step's poses back), and both run the slab test in the same
/// operation order; the GPU may fuse a multiply and an add (one rounding instead of two), so
/// the box-frame coordinates can differ by an ulp or two of the scene's coordinates (below
/// 1e-6 m at 10 m). A time of impact then moves by that over the ray's speed across the
/// entered face, `|dir . normal|`: the tolerance is `|toi_gpu - toi_cpu| * |dir . normal|
/// <= 1e-5 m`, ten times the ulps above. A hit at 0 (a ray starting inside) must be 0 with a
/// zero normal on both. Normals are rotated unit axes: within 1e-5 of each other. The test
/// also prints how many times are bit-equal (all of them on lavapipe), which depends on the
/// GPU's compiler and so is reported, not asserted.
#[test]
fn gpu_ray_batch_equals_the_cpu_ray_cast() {
    if GpuContext::for_tests().is_none() {
        return;
    }
    let world = random_world(Backend::Gpu, 17);
    let rays = random_rays(&world, 18);
    let max_toi = 20.0;
    let read_before = world.readback_bytes();
    let gpu = world.cast_rays_gpu(&rays, max_toi).expect("GPU batch");
    // Nothing of the world was read back for the batch (the rays' hits come back on their own).
    assert_eq!(world.readback_bytes(), read_before);
    assert_eq!(gpu.len(), rays.len());
    let (mut hits, mut inside, mut bit_equal, mut twins, mut worst) = (0, 0, 0, 0, 0.0f32);
    let twin_first = world.handles()[64];
    for (i, (ray, g)) in rays.iter().zip(&gpu).enumerate() {
        let c = world
            .cast_ray(ray.origin, ray.dir, max_toi, QueryFilter::default())
            .unwrap();
        let (g, c) = match (g, c) {
            (None, None) => continue,
            (Some(g), Some(c)) => (g, c),
            (g, c) => panic!("ray {i} {ray:?}: GPU {g:?}, CPU {c:?}"),
        };
        hits += 1;
        assert_eq!(g.body, c.body, "ray {i} {ray:?}: GPU {g:?}, CPU {c:?}");
        twins += usize::from(c.body == twin_first);
        if c.toi == 0.0 {
            inside += 1;
            assert_eq!(g.toi, 0.0, "ray {i}: {g:?} {c:?}");
            assert_eq!(g.normal, Vec3::zeros(), "ray {i}: {g:?} {c:?}");
            continue;
        }
        let err = (g.toi - c.toi).abs() * ray.dir.dot(&c.normal).abs();
        worst = worst.max(err);
        assert!(err <= 1e-5, "ray {i} {ray:?}: GPU {g:?}, CPU {c:?}");
        assert!((g.normal - c.normal).norm() <= 1e-5, "ray {i}: {g:?} {c:?}");
        assert!((g.point - c.point).norm() <= 1e-4, "ray {i}: {g:?} {c:?}");
        bit_equal += usize::from(g.toi.to_bits() == c.toi.to_bits());
    }
    println!(
        "{} rays: {hits} hits ({inside} from inside, {twins} on the first twin), \
         {bit_equal} of the others with bit-equal toi, worst |dtoi * dir.n| {worst:e} m",
        rays.len()
    );
    // The scene is dense enough that the comparison means something: many hits of each kind.
    assert!(hits > 1000, "{hits} hits");
    assert!(inside > 20, "{inside} rays start inside a body");
    assert!(twins > 0, "no ray reached the twin boxes");
}

/// Bad rays and `max_toi` are errors naming the field (and the ray's index), as for
/// `World::cast_ray`; the batch needs `Backend::Gpu` and a step after the last edit of the
/// bodies; an empty batch is an empty answer.
#[test]
fn gpu_ray_batch_contracts() {
    let cpu = random_world(Backend::Cpu, 3);
    let ray = Ray::new(Point3::new(0.0, 9.0, 0.0), -Vec3::y());
    expect_field(cpu.cast_rays_gpu(&[ray], 10.0), "backend");
    if GpuContext::for_tests().is_none() {
        return;
    }
    let mut world = World::new(WorldConfig {
        backend: Backend::Gpu,
        ..Default::default()
    })
    .expect("GPU world");
    let cube = world.add_body(BodyDesc::dynamic()).expect("cube");
    // Before any step the bodies are not on the GPU yet.
    expect_field(world.cast_rays_gpu(&[ray], 10.0), "world");
    world.step().expect("step");
    let hit = world.cast_rays_gpu(&[ray], 10.0).unwrap()[0].expect("the cube");
    assert_eq!(hit.body, cube);
    // Gravity moved the cube down by a few mm in one step: its top is just below y = 0.5.
    let top = world.pose(cube).unwrap().translation.vector.y + 0.5;
    assert!((hit.point.y - top).abs() < 1e-5, "{hit:?}, top {top}");
    assert!((hit.normal - Vec3::y()).norm() < 1e-6);
    assert_eq!(world.cast_rays_gpu(&[], 10.0).unwrap(), vec![]);

    let nan = Ray::new(Point3::new(Real::NAN, 0.0, 0.0), Vec3::y());
    let zero = Ray::new(Point3::origin(), Vec3::zeros());
    match world.cast_rays_gpu(&[ray, nan], 10.0) {
        Err(Error::InvalidValue { field, value, .. }) => {
            assert_eq!(field, "origin");
            assert!(value.contains("rays[1]"), "{value}");
        }
        other => panic!("{other:?}"),
    }
    expect_field(world.cast_rays_gpu(&[zero], 10.0), "dir");
    expect_field(world.cast_rays_gpu(&[ray], -1.0), "max_toi");
    expect_field(world.cast_rays_gpu(&[ray], Real::NAN), "max_toi");

    // A pose set since the step has not reached the GPU: refused until the next step.
    let mut moved = world.pose(cube).unwrap();
    moved.translation.vector.x += 3.0;
    world.set_pose(cube, moved).unwrap();
    expect_field(world.cast_rays_gpu(&[ray], 10.0), "world");
    world.step().unwrap();
    assert_eq!(world.cast_rays_gpu(&[ray], 10.0).unwrap(), vec![None]);
}

/// The kernel alone against its CPU twin `cast_rays_cpu` on buffers made for it (100 random
/// boxes, 2,000 random rays, a finite and an infinite `max_toi`): the same body or miss for
/// every ray and times within the tolerance of `gpu_ray_batch_equals_the_cpu_ray_cast`; and
/// buffers too small for the body count are refused, naming them.
#[test]
fn cast_rays_kernel_equals_its_cpu_twin() {
    use tumble::gpu::kernels::cast_rays::{GpuRay, cast_rays, cast_rays_cpu};
    use tumble::gpu::layout::{GpuPose, GpuShape};
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (poses, shapes): (Vec<GpuPose>, Vec<GpuShape>) = (0..100)
        .map(|_| {
            let c = Vec3::from_fn(|_, _| rng.random_range(-5.0..5.0));
            let pose = Pose::from_parts(c.into(), random_rotation(&mut rng));
            let h = Vec3::from_fn(|_, _| rng.random_range(0.05..0.8));
            let shape = GpuShape {
                hx: h.x,
                hy: h.y,
                hz: h.z,
                flags: 0,
            };
            (GpuPose::from_pose(&pose), shape)
        })
        .unzip();
    let rays: Vec<GpuRay> = (0..2000)
        .map(|_| {
            let o = Point3::from(Vec3::from_fn(|_, _| rng.random_range(-6.0..6.0)));
            GpuRay::new(&o, &random_dir(&mut rng))
        })
        .collect();
    let pose_buffer = ctx.storage_buffer("test poses", &poses);
    let shape_buffer = ctx.storage_buffer("test shapes", &shapes);
    for max_toi in [4.0, Real::INFINITY] {
        let gpu = cast_rays(&ctx, &pose_buffer, &shape_buffer, 100, &rays, max_toi).unwrap();
        let cpu = cast_rays_cpu(&poses, &shapes, &rays, max_toi);
        let mut hits = 0;
        for (i, ((g, c), ray)) in gpu.iter().zip(&cpu).zip(&rays).enumerate() {
            let (Some((gb, gt, gn)), Some((cb, ct, cn))) = (g.found(), c.found()) else {
                assert_eq!(g.found(), c.found(), "ray {i}");
                continue;
            };
            hits += 1;
            assert_eq!(gb, cb, "ray {i}: {g:?} {c:?}");
            let dir = Vec3::new(ray.dir[0], ray.dir[1], ray.dir[2]);
            assert!(
                (gt - ct).abs() * dir.dot(&cn).abs() <= 1e-5,
                "ray {i}: {g:?} {c:?}"
            );
            assert!((gn - cn).norm() <= 1e-5, "ray {i}: {g:?} {c:?}");
        }
        assert!(hits > 300, "max_toi {max_toi}: {hits} hits");
    }
    let e = cast_rays(&ctx, &pose_buffer, &shape_buffer, 101, &rays, 1.0).unwrap_err();
    assert!(e.to_string().contains("poses"), "{e}");
}
