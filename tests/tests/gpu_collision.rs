//! The GPU collision stages against their CPU twins on seeded random scenes: AABBs, sweep
//! axis, radix sort, the broad-phase pair list (exactly the CPU's), and the narrow phase's
//! manifolds (the same features and ids, positions and depths to 1e-4 of the box size,
//! normals to 1e-3 rad), pair matching and impulse carry (by id and by position).
//!
//! Runs on any adapter (lavapipe in CI, with `TUMBLE_REQUIRE_GPU=1` so a missing adapter
//! fails); without one and without that variable, each test prints "skipped" and passes.
// Tolerance checks are written `!(difference <= tolerance)` so that a NaN fails them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Aabb, Point3, Pose, Rot, Vec3, nalgebra::Translation3};
use tumble_gpu::collision::CollisionConfig;
use tumble_gpu::kernels::{
    carry_impulses::{CarryHistory, carry_impulses_cpu},
    choose_axis::choose_axis_cpu,
    collide_cuboids::{collide_pair_cpu, kind_code, kind_from_code},
    compact_touching::{compact_touching_cpu, scatter_impulses_cpu},
    gather_sweep_boxes::gather_sweep_boxes_cpu,
    match_pairs::match_pairs_cpu,
    plan_dispatch::plan_dispatch_cpu,
    radix_sort::{
        RadixBuffers, RadixSort, plan_passes, radix_sort_cpu, result_copy, tile_count_len,
    },
    update_aabbs::update_aabbs_cpu,
    write_sort_keys::write_sort_keys_cpu,
};
use tumble_gpu::layout::{GpuAabb, GpuContact, GpuPose, GpuShape, GpuVelocity, WorkList};
use tumble_gpu::{
    GpuCollision, GpuContext, GpuError, MAX_MANIFOLD_POINTS, ReadbackRequest, StageTimer,
};

/// A scene as the GPU takes it.
struct Scene {
    poses: Vec<GpuPose>,
    velocities: Vec<GpuVelocity>,
    shapes: Vec<GpuShape>,
}

fn random_rotation(rng: &mut ChaCha8Rng) -> Rot {
    Rot::from_euler_angles(
        rng.random_range(-3.2..3.2),
        rng.random_range(-1.6..1.6),
        rng.random_range(-3.2..3.2),
    )
}

/// `n` boxes scattered in a cube sized so that each overlaps a few others, 10 % static.
fn random_scene(n: usize, seed: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // About 1.3 m of space per box along each axis: boxes of 0.2 to 1.2 m then overlap about
    // three neighbours each, a dense but realistic pile.
    let side = 1.3 * (n as f32).cbrt();
    let mut scene = Scene {
        poses: Vec::new(),
        velocities: Vec::new(),
        shapes: Vec::new(),
    };
    for _ in 0..n {
        let is_static = rng.random_bool(0.1);
        let h = Vec3::new(
            rng.random_range(0.1..0.6),
            rng.random_range(0.1..0.6),
            rng.random_range(0.1..0.6),
        );
        let t = Vec3::new(
            rng.random_range(0.0..side),
            rng.random_range(0.0..side),
            rng.random_range(0.0..side),
        );
        let pose = Pose::from_parts(Translation3::from(t), random_rotation(&mut rng));
        let mut v = || {
            Vec3::new(
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
            )
        };
        let (lin, ang) = if is_static {
            (Vec3::zeros(), Vec3::zeros())
        } else {
            (v(), v())
        };
        scene.poses.push(GpuPose::from_pose(&pose));
        scene.velocities.push(GpuVelocity::new(lin, ang));
        scene.shapes.push(GpuShape::cuboid(
            &tumble_geometry::Cuboid::new(h),
            is_static,
        ));
    }
    scene
}

fn collision(ctx: &GpuContext, scene: &Scene, config: CollisionConfig) -> GpuCollision {
    let mut c = GpuCollision::new(ctx, config).expect("pipelines build");
    c.set_bodies(&scene.poses, &scene.velocities, &scene.shapes)
        .expect("valid scene");
    c
}

fn to_aabb(b: &GpuAabb) -> Aabb {
    Aabb::new(
        Point3::new(b.min[0], b.min[1], b.min[2]),
        Point3::new(b.max[0], b.max[1], b.max[2]),
    )
}

fn static_flags(scene: &Scene) -> Vec<bool> {
    scene.shapes.iter().map(GpuShape::is_static).collect()
}

#[test]
fn update_aabbs_matches_its_cpu_twin() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let scene = random_scene(1000, 1);
    let config = CollisionConfig::default();
    let mut gpu = collision(&ctx, &scene, config);
    gpu.step().unwrap();
    let got = gpu.read_aabbs().unwrap();
    let want = update_aabbs_cpu(
        &scene.poses,
        &scene.velocities,
        &scene.shapes,
        config.margin,
        config.dt,
    );
    // The two sides build the rotation matrix from the quaternion in different operation
    // orders: a few ulps of 1 on each entry, times extents below 1 m, plus the rounding of
    // coordinates up to 13 m (ulp 1e-6). 1e-5 m covers both with a margin of ten.
    let mut worst = 0.0f32;
    for (g, w) in got.iter().zip(&want) {
        for k in 0..3 {
            worst = worst
                .max((g.min[k] - w.min[k]).abs())
                .max((g.max[k] - w.max[k]).abs());
        }
    }
    assert!(worst < 1e-5, "largest AABB difference {worst} m");
    // And the swept box still contains the tight box of the geometry layer.
    for (i, g) in got.iter().enumerate() {
        let pose = tumble_gpu::kernels::update_aabbs::pose_from_gpu(&scene.poses[i]);
        let s = &scene.shapes[i];
        let tight = Aabb::from_cuboid(
            &tumble_geometry::Cuboid::new(Vec3::new(s.hx, s.hy, s.hz)),
            &pose,
            0.0,
        );
        for k in 0..3 {
            assert!(g.min[k] <= tight.min[k] + 1e-5 && g.max[k] >= tight.max[k] - 1e-5);
        }
    }
}

#[test]
fn sweep_axis_and_body_order_match_the_cpu() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // A slab: wide along z, so the axis is not a coin toss.
    let mut scene = random_scene(3000, 2);
    for p in &mut scene.poses {
        p.position[2] *= 4.0;
    }
    let mut gpu = collision(&ctx, &scene, CollisionConfig::default());
    gpu.step().unwrap();
    let aabbs = gpu.read_aabbs().unwrap();
    let axis = gpu.read_sweep_axis().unwrap();
    let want = choose_axis_cpu(&aabbs);
    assert_eq!(axis.axis, want.axis);
    assert_eq!(axis.axis, 2, "the slab is widest along z");
    for k in 0..3 {
        // Same summation order on both sides; fused multiply-adds on the GPU change the last
        // bits of each of the 3000 squares: 1e-4 relative.
        let rel = (axis.variance[k] - want.variance[k]).abs() / want.variance[k];
        assert!(
            rel < 1e-4,
            "variance {k}: {} vs {}",
            axis.variance[k],
            want.variance[k]
        );
    }
    // The sorted order is exactly the CPU's stable sort of the same keys.
    let (keys, bodies) = gpu.read_sorted_bodies().unwrap();
    let (k0, v0) = write_sort_keys_cpu(&aabbs, axis.axis);
    let (want_keys, want_bodies) = radix_sort_cpu(&k0, &v0, 32);
    assert_eq!(keys, want_keys);
    assert_eq!(bodies, want_bodies);
    // And the boxes in sweep order, sweep axis first, are exactly the CPU's gather.
    let want_boxes = gather_sweep_boxes_cpu(&aabbs, &scene.shapes, &bodies, axis.axis);
    assert_eq!(gpu.read_sweep_boxes().unwrap(), want_boxes);
}

/// Runs the radix sort alone on `keys`/`values` with the count given on the GPU.
fn gpu_sort(
    ctx: &GpuContext,
    keys: &[u32],
    values: &[u32],
    sorts: &[(bool, u32)],
) -> (Vec<u32>, Vec<u32>) {
    let n = keys.len() as u32;
    let sort = RadixSort::new(ctx).unwrap();
    let work = ctx.storage_buffer("work", &[WorkList::for_count(n)]);
    let k = [
        ctx.storage_buffer("k0", keys),
        ctx.storage_buffer("k1", keys),
    ];
    let v = [
        ctx.storage_buffer("v0", values),
        ctx.storage_buffer("v1", values),
    ];
    let tiles = ctx.storage_buffer("tiles", &vec![0u32; tile_count_len(n) as usize]);
    let passes = plan_passes(sorts);
    let groups = sort.bind(
        ctx,
        &RadixBuffers {
            work: &work,
            first: [&k[0], &k[1]],
            second: [&v[0], &v[1]],
            tile_counts: &tiles,
        },
        &passes,
    );
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    {
        let mut timer = StageTimer::disabled(ctx);
        let mut pass = timer.begin_pass(&mut encoder, "sort");
        sort.record(&mut pass, &groups, &work);
    }
    ctx.queue.submit([encoder.finish()]);
    let r = result_copy(&passes);
    (
        ctx.read_buffer(&k[r], 0, u64::from(n)).unwrap(),
        ctx.read_buffer(&v[r], 0, u64::from(n)).unwrap(),
    )
}

#[test]
fn radix_sort_is_a_stable_sort_equal_to_the_cpu() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    // 70,001 keys: many tiles and a partial last tile. Keys from a small range repeat a lot,
    // so stability is visible in the values (the original positions).
    for (n, range) in [(70_001usize, 1000u32), (1000, u32::MAX)] {
        let keys: Vec<u32> = (0..n).map(|_| rng.random_range(0..range)).collect();
        let values: Vec<u32> = (0..n as u32).collect();
        let got = gpu_sort(&ctx, &keys, &values, &[(true, 32)]);
        assert_eq!(got, radix_sort_cpu(&keys, &values, 32), "n = {n}");
    }
    // Two chained sorts with roles swapped: lexicographic order of (first, second).
    let a: Vec<u32> = (0..5000).map(|_| rng.random_range(0..300)).collect();
    let b: Vec<u32> = (0..5000).map(|_| rng.random_range(0..300)).collect();
    let (sa, sb) = gpu_sort(&ctx, &a, &b, &[(false, 9), (true, 9)]);
    let mut want: Vec<(u32, u32)> = a.iter().copied().zip(b.iter().copied()).collect();
    want.sort();
    assert_eq!(sa.into_iter().zip(sb).collect::<Vec<_>>(), want);
}

/// GPU pairs against `tumble_broad` on the GPU's own AABBs (so the comparison is of the broad
/// phase alone, exactly).
fn pairs_equal_cpu(n: usize, seed: u64) {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let scene = random_scene(n, seed);
    let mut gpu = collision(&ctx, &scene, CollisionConfig::default());
    let snap = gpu
        .step_and_read(ReadbackRequest {
            pairs: true,
            aabbs: true,
            ..Default::default()
        })
        .unwrap();
    let aabbs: Vec<Aabb> = snap.aabbs.iter().map(to_aabb).collect();
    let cpu = tumble_broad::sweep_and_prune_filtered(&aabbs, &static_flags(&scene)).unwrap();
    // A dense pile: the test is only meaningful with plenty of pairs.
    assert!(cpu.len() > n, "only {} pairs", cpu.len());
    assert_eq!(snap.pairs.len(), cpu.len());
    assert!(snap.pairs == cpu, "GPU pair list differs from the CPU's");
}

#[test]
fn gpu_pairs_equal_cpu_pairs_on_1000_random_boxes() {
    pairs_equal_cpu(1000, 4);
}

#[test]
fn gpu_pairs_equal_cpu_pairs_on_20000_random_boxes() {
    pairs_equal_cpu(20_000, 5);
}

#[test]
fn exactly_touching_boxes_pair_and_static_pairs_do_not() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // A 10 x 10 x 10 grid of unit cubes at unit spacing: every AABB exactly touches its 26
    // neighbours (closed intervals: all pairs). The bottom layer is static.
    let mut scene = Scene {
        poses: vec![],
        velocities: vec![],
        shapes: vec![],
    };
    for i in 0..1000 {
        let (x, y, z) = ((i % 10) as f32, ((i / 10) % 10) as f32, (i / 100) as f32);
        scene
            .poses
            .push(GpuPose::from_pose(&Pose::translation(x, y, z)));
        scene.velocities.push(GpuVelocity::default());
        scene.shapes.push(GpuShape::cuboid(
            &tumble_geometry::Cuboid::new(Vec3::repeat(0.5)),
            y == 0.0,
        ));
    }
    let config = CollisionConfig {
        margin: 0.0,
        dt: 0.0,
        ..Default::default()
    };
    let mut gpu = collision(&ctx, &scene, config);
    let snap = gpu
        .step_and_read(ReadbackRequest {
            pairs: true,
            ..Default::default()
        })
        .unwrap();
    let cpu_aabbs: Vec<Aabb> = scene
        .poses
        .iter()
        .map(|p| {
            let c = Point3::new(p.position[0], p.position[1], p.position[2]);
            Aabb::new(c - Vec3::repeat(0.5), c + Vec3::repeat(0.5))
        })
        .collect();
    let cpu = tumble_broad::sweep_and_prune_filtered(&cpu_aabbs, &static_flags(&scene)).unwrap();
    // Each pair of cells one step apart in any of the 13 forward directions touches: the
    // count for direction d is the product over axes of (10 - |d_k|). The static bottom layer
    // (y = 0) loses its in-layer pairs, the directions with d_y = 0.
    let mut all = 0;
    let mut in_layer = 0;
    for dx in -1i32..=1 {
        for dy in -1i32..=1 {
            for dz in -1i32..=1 {
                let d = [dx, dy, dz];
                // One of each opposite pair: the first non-zero component positive.
                if d.iter().find(|&&c| c != 0).is_none_or(|&c| c < 0) {
                    continue;
                }
                let cells: i32 = d.iter().map(|c| 10 - c.abs()).product();
                all += cells;
                if dy == 0 {
                    in_layer += cells / 10;
                }
            }
        }
    }
    assert_eq!(cpu.len() as i32, all - in_layer);
    assert_eq!(snap.pairs, cpu);
}

#[test]
fn pair_overflow_is_reported_and_growing_recovers_the_exact_list() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let scene = random_scene(2000, 6);
    let tight = CollisionConfig {
        pairs_per_body: 1,
        min_pair_capacity: 64,
        auto_grow: false,
        ..Default::default()
    };
    let mut gpu = collision(&ctx, &scene, tight);
    let request = ReadbackRequest {
        pairs: true,
        manifolds: true,
        aabbs: true,
        touching: true,
    };
    let err = gpu.step_and_read(request).unwrap_err();
    let GpuError::PairOverflow {
        requested,
        capacity,
    } = err
    else {
        panic!("{err}")
    };
    assert_eq!(capacity, 2000);
    // The counter kept counting past the end: it holds the true number of pairs.
    let aabbs: Vec<Aabb> = gpu.read_aabbs().unwrap().iter().map(to_aabb).collect();
    let cpu = tumble_broad::sweep_and_prune_filtered(&aabbs, &static_flags(&scene)).unwrap();
    assert_eq!(requested as usize, cpu.len());
    // The work list the GPU planned from its counter is exactly the CPU twin's: the clamped
    // count and the dispatch covering it (read through the low-level path, which returns
    // the snapshot without judging the overflow).
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    gpu.record(&mut encoder, &mut StageTimer::disabled(&ctx))
        .unwrap();
    let plan = gpu
        .record_readback(&mut encoder, ReadbackRequest::default())
        .unwrap();
    ctx.queue.submit([encoder.finish()]);
    let pending = gpu.submit_readback(plan);
    let snap = gpu.receive(pending).unwrap();
    assert_eq!(snap.work, plan_dispatch_cpu(requested, capacity));
    assert!(snap.check_overflow().is_err());
    let mut grows = collision(
        &ctx,
        &scene,
        CollisionConfig {
            auto_grow: true,
            ..tight
        },
    );
    let snap = grows.step_and_read(request).unwrap();
    assert!(grows.pair_capacity() >= requested);
    assert_eq!(snap.pairs, cpu);
}

/// Pairs of boxes near contact, one pair per cell of a grid 6 m apart: faces resting on
/// faces with small tilts, crossed edges, and pairs in general position, some overlapping,
/// some apart within the margin, some beyond it.
fn contact_pairs(pairs: usize, seed: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut scene = Scene {
        poses: vec![],
        velocities: vec![],
        shapes: vec![],
    };
    let per_axis = (pairs as f32).cbrt().ceil() as usize;
    let spacing = 6.0;
    let origin = -0.5 * spacing * per_axis as f32;
    for k in 0..pairs {
        let cell = Vec3::new(
            (k % per_axis) as f32,
            ((k / per_axis) % per_axis) as f32,
            (k / (per_axis * per_axis)) as f32,
        );
        let ha = Vec3::new(
            rng.random_range(0.2..1.2),
            rng.random_range(0.2..1.2),
            rng.random_range(0.2..1.2),
        );
        let hb = Vec3::new(
            rng.random_range(0.2..1.2),
            rng.random_range(0.2..1.2),
            rng.random_range(0.2..1.2),
        );
        let rot_a = random_rotation(&mut rng);
        let ta = cell * spacing + Vec3::repeat(origin);
        let pose_b = match rng.random_range(0..10) {
            // B on one of A's faces: aligned up to a small tilt (which makes face choices and
            // hysteresis matter), slid sideways, from 2 cm deep to 2 cm apart.
            0..=3 => {
                let axis = rng.random_range(0..3);
                let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
                let tilt = Rot::from_euler_angles(
                    rng.random_range(-0.05..0.05),
                    rng.random_range(-0.05..0.05),
                    rng.random_range(-0.05..0.05),
                );
                let rot_b = rot_a * tilt;
                let n = rot_a * Vec3::ith(axis, sign);
                let radius_b = (0..3)
                    .map(|j| (rot_b * Vec3::ith(j, 1.0)).dot(&n).abs() * hb[j])
                    .sum::<f32>();
                let mut lateral = Vec3::zeros();
                for j in (0..3).filter(|&j| j != axis) {
                    lateral += rot_a * Vec3::ith(j, rng.random_range(-ha[j]..ha[j]));
                }
                let gap = rng.random_range(-0.02..0.02);
                Pose::from_parts(
                    Translation3::from(ta + n * (ha[axis] + radius_b + gap) + lateral),
                    rot_b,
                )
            }
            // Anywhere around A, from deep overlap to just past touching.
            _ => {
                let dir = Vec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                )
                .try_normalize(1e-3)
                .unwrap_or(Vec3::x());
                let reach = rng.random_range(0.3..1.05) * (ha.norm() + hb.norm());
                Pose::from_parts(
                    Translation3::from(ta + dir * reach),
                    random_rotation(&mut rng),
                )
            }
        };
        let pose_a = Pose::from_parts(Translation3::from(ta), rot_a);
        for (pose, h) in [(pose_a, ha), (pose_b, hb)] {
            scene.poses.push(GpuPose::from_pose(&pose));
            scene.velocities.push(GpuVelocity::default());
            scene
                .shapes
                .push(GpuShape::cuboid(&tumble_geometry::Cuboid::new(h), false));
        }
    }
    scene
}

/// Position and depth tolerance of a pair: 1e-4 of its largest half extent, plus four f32
/// ulps of the world coordinate, which the CPU and the GPU round independently when they
/// bring the points back to world space.
fn length_tolerance(scene: &Scene, (a, b): (u32, u32), coordinate: f32) -> f32 {
    let size = |i: u32| {
        let s = &scene.shapes[i as usize];
        s.hx.max(s.hy).max(s.hz)
    };
    1e-4 * size(a).max(size(b)) + 4.0 * f32::EPSILON * coordinate.abs()
}

/// Normal tolerance: 1e-3 rad.
const NORMAL_TOLERANCE_RAD: f32 = 1e-3;

/// Why a GPU manifold differs from the CPU's, or `None` when they agree within tolerance.
fn manifold_difference(
    scene: &Scene,
    pair: (u32, u32),
    gpu: Option<tumble_geometry::Manifold>,
    cpu: Option<tumble_geometry::Manifold>,
) -> Option<String> {
    let (g, c) = match (gpu, cpu) {
        (None, None) => return None,
        (Some(_), None) => return Some("GPU contact, CPU none".into()),
        (None, Some(_)) => return Some("CPU contact, GPU none".into()),
        (Some(g), Some(c)) => (g, c),
    };
    if (g.kind, g.feature) != (c.kind, c.feature) {
        return Some(format!(
            "feature {:?}/{} vs {:?}/{}",
            g.kind, g.feature, c.kind, c.feature
        ));
    }
    let ids = |m: &tumble_geometry::Manifold| m.points().iter().map(|p| p.id).collect::<Vec<_>>();
    if ids(&g) != ids(&c) {
        return Some(format!("ids {:?} vs {:?}", ids(&g), ids(&c)));
    }
    let angle = g.normal.angle(&c.normal);
    if !(angle <= NORMAL_TOLERANCE_RAD) {
        return Some(format!("normal off by {angle} rad"));
    }
    for (pg, pc) in g.points().iter().zip(c.points()) {
        let scale = pc.position.coords.amax();
        let tol = length_tolerance(scene, pair, scale);
        let dp = (pg.position - pc.position).norm();
        if !(dp <= tol) {
            return Some(format!("point {} off by {dp} (tolerance {tol})", pc.id));
        }
        let dd = (pg.depth - pc.depth).abs();
        if !(dd <= length_tolerance(scene, pair, 0.0)) {
            return Some(format!("depth of point {} off by {dd}", pc.id));
        }
    }
    None
}

/// True when the CPU itself returns the GPU's answer for an input within rounding of the
/// original: the two sides then differ only by which side of a near-tie (a face-choice
/// tolerance, a clipping plane, an argmax) their own rounding landed on.
fn is_near_tie(
    scene: &Scene,
    pair: (u32, u32),
    previous: Option<(tumble_geometry::FeatureKind, u32)>,
    gpu: Option<tumble_geometry::Manifold>,
    config: &CollisionConfig,
) -> bool {
    let mut rng = ChaCha8Rng::seed_from_u64(u64::from(pair.0) << 32 | u64::from(pair.1));
    // 20 f32 ulps of the coordinates and 1e-6 rad: the size of the disagreement between two
    // roundings of the same transform chain, a hundred times below the test's tolerances.
    for _ in 0..32 {
        let mut poses = scene.poses.clone();
        for i in [pair.0, pair.1] {
            let p = &mut poses[i as usize];
            for k in 0..3 {
                let ulp = 20.0 * f32::EPSILON * p.position[k].abs().max(1.0);
                p.position[k] += rng.random_range(-ulp..ulp);
            }
            let pose = tumble_gpu::kernels::update_aabbs::pose_from_gpu(p);
            let nudge = Rot::from_scaled_axis(Vec3::new(
                rng.random_range(-1e-6..1e-6),
                rng.random_range(-1e-6..1e-6),
                rng.random_range(-1e-6..1e-6),
            ));
            *p = GpuPose::from_pose(&Pose::from_parts(pose.translation, nudge * pose.rotation));
        }
        let cpu = collide_pair_cpu(
            &poses,
            &scene.velocities,
            &scene.shapes,
            pair,
            previous,
            config.margin,
            config.dt,
        );
        if manifold_difference(scene, pair, gpu, cpu).is_none() {
            return true;
        }
    }
    false
}

/// Compares every GPU manifold of `snap` with the CPU's; returns (compared, near ties), and
/// fails on any difference no near tie explains.
fn compare_manifolds(
    scene: &Scene,
    snap: &tumble_gpu::CollisionSnapshot,
    previous: impl Fn(usize) -> Option<(tumble_geometry::FeatureKind, u32)>,
    config: &CollisionConfig,
) -> (usize, usize) {
    let mut near_ties = 0;
    let mut unexplained = Vec::new();
    for (k, &pair) in snap.pairs.iter().enumerate() {
        let gpu = snap.manifold(k);
        let cpu = collide_pair_cpu(
            &scene.poses,
            &scene.velocities,
            &scene.shapes,
            pair,
            previous(k),
            config.margin,
            config.dt,
        );
        if let Some(why) = manifold_difference(scene, pair, gpu, cpu) {
            if is_near_tie(scene, pair, previous(k), gpu, config) {
                near_ties += 1;
                eprintln!("near tie, pair {pair:?}: {why}");
            } else {
                unexplained.push(format!("pair {pair:?}: {why}"));
            }
        }
    }
    assert!(
        unexplained.is_empty(),
        "{} unexplained differences:\n{}",
        unexplained.len(),
        unexplained.join("\n")
    );
    (snap.pairs.len(), near_ties)
}

#[test]
fn gpu_manifolds_match_the_cpu_narrow_phase_on_10000_random_pairs() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // 11,000 designed pairs: a few end with AABBs apart (no candidate), so that at least
    // 10,000 candidate pairs are compared.
    let scene = contact_pairs(11_000, 7);
    let config = CollisionConfig::default();
    let mut gpu = collision(&ctx, &scene, config);
    let snap = gpu.step_and_read(ReadbackRequest::CONTACTS).unwrap();
    // Every designed pair whose AABBs overlap is a candidate (a few neighbouring cells may
    // add more).
    assert!(
        snap.pairs.len() >= 10_000,
        "{} candidate pairs",
        snap.pairs.len()
    );
    let touching = (0..snap.pairs.len())
        .filter(|&k| snap.manifolds[k].len > 0)
        .count();
    assert!(touching >= 5_000, "only {touching} pairs in contact");
    let (compared, near_ties) = compare_manifolds(&scene, &snap, |_| None, &config);
    eprintln!("{compared} pairs compared, {touching} in contact, {near_ties} near ties");
    // Near ties are rounding on a knife edge; more than 1 % would mean a systematic bias.
    assert!(
        near_ties * 100 <= compared,
        "{near_ties} near ties of {compared}"
    );
}

#[test]
fn second_step_keeps_features_by_hysteresis_and_carries_impulses_by_id_and_position() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let mut scene = contact_pairs(3_000, 8);
    let config = CollisionConfig::default();
    let mut gpu = collision(&ctx, &scene, config);
    let first = gpu.step_and_read(ReadbackRequest::CONTACTS).unwrap();
    let first_locals = gpu.read_local_manifolds().unwrap();
    // Impulses a solver would have left: distinct per point, so a wrong match shows.
    let mut stored = first.contacts.clone();
    for (i, c) in stored.iter_mut().enumerate() {
        c.normal_impulse = 1.0 + i as f32;
        c.friction_impulse = [i as f32, -(i as f32), 0.5, 0.0];
    }
    gpu.store_contacts(0, &stored).unwrap();

    // Every second body moves a little: a millimetre and a quarter degree.
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for p in scene.poses.iter_mut().skip(1).step_by(2) {
        let pose = tumble_gpu::kernels::update_aabbs::pose_from_gpu(p);
        let nudge = Rot::from_scaled_axis(Vec3::new(
            rng.random_range(-4e-3..4e-3),
            rng.random_range(-4e-3..4e-3),
            0.0,
        ));
        let shift = Vec3::new(
            rng.random_range(-1e-3..1e-3),
            rng.random_range(-1e-3..1e-3),
            rng.random_range(-1e-3..1e-3),
        );
        *p = GpuPose::from_pose(&Pose::from_parts(
            Translation3::from(pose.translation.vector + shift),
            nudge * pose.rotation,
        ));
    }
    gpu.set_motion(&scene.poses, &scene.velocities).unwrap();
    let second = gpu.step_and_read(ReadbackRequest::CONTACTS).unwrap();

    // Each pair found last step's index by binary search, exactly as the CPU finds it.
    let previous_index = match_pairs_cpu(&second.pairs, &first.pairs);
    let got: Vec<u32> = second.manifolds.iter().map(|m| m.previous).collect();
    assert_eq!(got, previous_index);
    // The narrow phase kept last step's reference face where the CPU keeps it.
    let previous = |k: usize| {
        let p = previous_index[k];
        (p != tumble_gpu::constants::NO_PREVIOUS && first.manifolds[p as usize].len > 0).then(
            || {
                let m = &first.manifolds[p as usize];
                (kind_from_code(m.kind), m.feature)
            },
        )
    };
    let (compared, near_ties) = compare_manifolds(&scene, &second, previous, &config);
    assert!(
        near_ties * 100 <= compared,
        "{near_ties} near ties of {compared}"
    );
    // Hysteresis was exercised: some pair kept a face that is not its best one any more.
    let kept = (0..second.pairs.len())
        .filter(|&k| {
            let Some((kind, feature)) = previous(k) else {
                return false;
            };
            let m = &second.manifolds[k];
            m.len > 0 && kind_code(kind) == m.kind && feature == m.feature && {
                let pair = second.pairs[k];
                let fresh = collide_pair_cpu(
                    &scene.poses,
                    &scene.velocities,
                    &scene.shapes,
                    pair,
                    None,
                    config.margin,
                    config.dt,
                );
                fresh.is_some_and(|f| (f.kind, f.feature) != (kind, feature))
            }
        })
        .count();
    assert!(
        kept > 0,
        "no pair needed hysteresis; the scene does not test it"
    );

    // Impulses: copied exactly (no arithmetic), so compare exactly with the CPU twin.
    let mut want: Vec<GpuContact> = second.contacts.clone();
    for c in &mut want {
        c.normal_impulse = 0.0;
        c.friction_impulse = [0.0; 4];
    }
    let second_locals = carry_impulses_cpu(
        &scene.poses,
        &second.manifolds,
        &mut want,
        &CarryHistory {
            manifolds: &first.manifolds,
            contacts: &stored,
            locals: &first_locals,
        },
    );
    assert_eq!(second.contacts, want);
    // The manifolds kept for the next step are this step's in A's frame: the twin rotates in
    // the shader's arithmetic, so they differ only by the round-off of world coordinates up
    // to 45 m (f32 spacing 4e-6 m, fused or not): 1e-5 m, a thousandth of the 1 cm reach.
    let gpu_locals = gpu.read_local_manifolds().unwrap();
    assert_eq!(gpu_locals.len(), second_locals.len());
    let mut worst = 0.0f32;
    for (k, m) in second.manifolds.iter().enumerate() {
        let (g, c) = (&gpu_locals[k], &second_locals[k]);
        let slots = std::iter::once((&g.normal, &c.normal))
            .chain(g.points.iter().zip(&c.points).take(m.len as usize));
        for (a, b) in slots.filter(|_| m.len > 0) {
            for i in 0..4 {
                worst = worst.max((a[i] - b[i]).abs());
            }
        }
    }
    assert!(!(worst > 1e-5), "local manifolds differ by {worst}");
    let carried = second
        .contacts
        .iter()
        .filter(|c| c.normal_impulse > 0.0)
        .count();
    assert!(
        carried * 2
            > second
                .manifolds
                .iter()
                .map(|m| m.len as usize)
                .sum::<usize>(),
        "most points persist over a small motion"
    );
    let _ = MAX_MANIFOLD_POINTS;
}

#[test]
fn bad_input_and_oversized_buffers_are_errors_naming_the_field() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let mut scene = random_scene(10, 10);
    let mut gpu = collision(&ctx, &scene, CollisionConfig::default());
    scene.poses[3].position[1] = f32::NAN;
    let err = gpu.set_motion(&scene.poses, &scene.velocities).unwrap_err();
    assert!(err.to_string().contains("poses[3].position"), "{err}");
    scene.poses[3].position[1] = 0.0;
    scene.poses[4].rotation = [0.0, 0.0, 0.0, 2.0];
    let err = gpu
        .set_bodies(&scene.poses, &scene.velocities, &scene.shapes)
        .unwrap_err();
    assert!(err.to_string().contains("poses[4].rotation"), "{err}");
    scene.poses[4].rotation = [0.0, 0.0, 0.0, 1.0];
    scene.shapes[5].hy = -1.0;
    let err = gpu
        .set_bodies(&scene.poses, &scene.velocities, &scene.shapes)
        .unwrap_err();
    assert!(err.to_string().contains("shapes[5].hy"), "{err}");
    let err = gpu
        .set_bodies(&scene.poses[..9], &scene.velocities, &scene.shapes)
        .unwrap_err();
    assert!(err.to_string().contains("velocities.len()"), "{err}");
    // Four points of 48 bytes per pair slot: a billion slots is far past any device's
    // largest storage binding, and the error names the buffer and the limit.
    let err = gpu.reserve_pairs(1 << 30).unwrap_err();
    let GpuError::LimitExceeded {
        what, limit_name, ..
    } = &err
    else {
        panic!("{err}")
    };
    assert_eq!(*limit_name, "max_storage_buffer_binding_size");
    assert!(
        what.contains("pair") || what.contains("contacts") || what.contains("manifolds"),
        "{what}"
    );
    // The collision object is still usable after refused input.
    scene.shapes[5].hy = 0.3;
    gpu.set_bodies(&scene.poses, &scene.velocities, &scene.shapes)
        .unwrap();
    gpu.step_and_read(ReadbackRequest::CONTACTS).unwrap();
}

#[test]
fn touching_readback_is_the_dense_list_of_the_per_pair_manifolds_and_impulses_scatter_back() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let scene = contact_pairs(3_000, 11);
    let mut gpu = collision(&ctx, &scene, CollisionConfig::default());
    let both = ReadbackRequest {
        touching: true,
        ..ReadbackRequest::CONTACTS
    };
    // Two steps: the first readback is sized from no history (1024 manifolds) and must
    // fetch the rest; the second is sized from the first.
    for _ in 0..2 {
        let snap = gpu.step_and_read(both).unwrap();
        let want = compact_touching_cpu(&snap.manifolds, &snap.contacts);
        assert!(
            want.manifolds.len() > 1024,
            "the scene must overflow the first guess"
        );
        assert_eq!(snap.touching, want);
        assert_eq!(
            snap.touching_counts.manifolds as usize,
            want.manifolds.len()
        );
        assert_eq!(snap.touching_counts.points as usize, want.points.len());
        // Both readbacks give the solver the same contacts.
        let dense_only = tumble_gpu::CollisionSnapshot {
            manifolds: vec![],
            contacts: vec![],
            ..snap.clone()
        };
        assert_eq!(dense_only.solver_contacts(), snap.solver_contacts());
    }

    // Impulses given in dense order land in the per-pair slots, as the CPU twin puts them.
    let snap = gpu.step_and_read(both).unwrap();
    let impulses: Vec<GpuContact> = (0..snap.touching.points.len())
        .map(|i| GpuContact {
            normal_impulse: 1.0 + i as f32,
            friction_impulse: [0.5, i as f32, -1.0, 0.0],
            ..Default::default()
        })
        .collect();
    gpu.store_touching_impulses(&impulses).unwrap();
    let per_pair = ctx
        .read_buffer::<GpuContact>(gpu.buffers().contacts, 0, snap.contacts.len() as u64)
        .unwrap();
    let mut want = snap.contacts.clone();
    scatter_impulses_cpu(&snap.touching, &impulses, &mut want);
    assert_eq!(per_pair, want);
    // A wrong length is refused, naming it.
    let err = gpu.store_touching_impulses(&impulses[1..]).unwrap_err();
    assert!(err.to_string().contains("impulses.len()"), "{err}");
}
