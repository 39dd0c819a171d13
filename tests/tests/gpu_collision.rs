//! The GPU collision stages against their CPU twins on seeded random scenes: AABBs, sweep
//! axis and body order, the broad-phase pair list (exactly the CPU's, also sorted world by
//! world in a step of many small worlds), pair overflow and growth, bad input, and the
//! touching readback. The sorts on their own are in `gpu_sorts.rs`, the narrow phase's checks
//! in `gpu_narrow.rs`, the long boxes of the broad phase in `gpu_broad_phase.rs`.
//!
//! Runs on any adapter (lavapipe in CI, with `TUMBLE_REQUIRE_GPU=1` so a missing adapter
//! fails); without one and without that variable, each test prints "skipped" and passes.
// Tolerance checks are written `!(difference <= tolerance)` so that a NaN fails them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Aabb, Point3, Pose, Vec3};
use tumble_gpu::collision::CollisionConfig;
use tumble_gpu::kernels::{
    choose_axis::choose_axis_cpu,
    compact_touching::{compact_touching_cpu, scatter_impulses_cpu},
    cuboid_from_gpu,
    gather_sweep_boxes::gather_sweep_boxes_cpu,
    plan_dispatch::plan_dispatch_cpu,
    radix_sort::radix_sort_cpu,
    rank_sort::sort_world_pairs_cpu,
    update_aabbs::pose_from_gpu,
    velocity_from_gpu,
    write_sort_keys::write_sort_keys_cpu,
};
use tumble_gpu::layout::{GpuContact, GpuPose, GpuShape, GpuVelocity};
use tumble_gpu::{GpuContext, GpuError, ReadbackRequest, StageTimer};
use tumble_tests::gpu_scene::{
    Scene, collision, contact_pairs, random_scene, static_flags, step_pairs_and_aabbs, to_aabb,
};

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
    let shapes: Vec<_> = scene.shapes.iter().map(cuboid_from_gpu).collect();
    let poses: Vec<_> = scene.poses.iter().map(pose_from_gpu).collect();
    let (linear, angular): (Vec<_>, Vec<_>) =
        scene.velocities.iter().map(velocity_from_gpu).unzip();
    let want =
        tumble_broad::update_aabbs(&shapes, &poses, &linear, &angular, config.margin, config.dt);
    // Not bitwise: the two sides build the rotation matrix from the quaternion in different
    // operation orders (a few ulps of 1 on each entry, times extents below 1 m), and the kernel
    // adds margin and spin before building the box and then the travel, where the CPU stage
    // grows the box by the margin first, then by travel and turn (a few ulps of coordinates up
    // to 13 m, ulp 1e-6). 1e-5 m covers both with a margin of ten, while a missing travel or
    // spin (centimetres at these speeds) still fails.
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
    // A slab: wide along z, so the axis is not a coin toss. 3000 bodies take the radix sort,
    // 700 the one-workgroup rank sort (at most RANK_SORT_CAPACITY): both must give the CPU's
    // stable order.
    for n in [3000, 700] {
        check_axis_and_order(&ctx, n);
    }
}

fn check_axis_and_order(ctx: &GpuContext, n: usize) {
    let mut scene = random_scene(n, 2);
    for p in &mut scene.poses {
        p.position[2] *= 4.0;
    }
    let mut gpu = collision(ctx, &scene, CollisionConfig::default());
    gpu.step().unwrap();
    let aabbs = gpu.read_aabbs().unwrap();
    let axis = gpu.read_sweep_axis().unwrap();
    let want = choose_axis_cpu(&aabbs);
    assert_eq!(axis.axis, want.axis);
    assert_eq!(axis.axis, 2, "the slab is widest along z");
    for k in 0..3 {
        // Same summation order on both sides; fused multiply-adds on the GPU change the last
        // bits of each of the n squares: 1e-4 relative.
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

/// GPU pairs against `tumble_broad` on the GPU's own AABBs (so the comparison is of the broad
/// phase alone, exactly).
fn pairs_equal_cpu(n: usize, seed: u64) {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let scene = random_scene(n, seed);
    let mut gpu = collision(&ctx, &scene, CollisionConfig::default());
    let (snap, aabbs) = step_pairs_and_aabbs(&mut gpu);
    let cpu = tumble_broad::sweep_and_prune_filtered(&aabbs, &static_flags(&scene)).unwrap();
    // A dense pile: the test is only meaningful with plenty of pairs.
    assert!(cpu.len() > n, "only {} pairs", cpu.len());
    assert_eq!(snap.pairs.len(), cpu.len());
    assert!(snap.pairs == cpu, "GPU pair list differs from the CPU's");
}

#[test]
fn a_step_of_small_worlds_sorts_bodies_and_pairs_by_world_into_the_cpus_pair_order() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // 600 worlds in the same region of space, each a random pile of 2 to 45 boxes: small
    // enough that the step sorts its bodies and its pairs one workgroup per world. The pairs
    // must be exactly the CPU's sweep of each world alone, offset by the world's first body,
    // world after world: a pair across worlds, a pair lost or repeated by the count, scan or
    // scatter, or a world's run out of (a, b) order would differ. World 0 puts its 45 boxes
    // (the most the pair sort by world takes) almost on one spot, so its pairs come near the
    // 990 that a world of 45 boxes can form, the rank sort's near-full case.
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut scene = Scene {
        poses: vec![],
        velocities: vec![],
        shapes: vec![],
    };
    let mut firsts = vec![];
    for w in 0..600u32 {
        // More worlds than the scan's workgroup has threads (each thread then scans a run of
        // three worlds); every 20th world up to the largest size the sort by world takes.
        let n = match w {
            0 => 45,
            w if w % 20 == 0 => rng.random_range(2..=45),
            _ => rng.random_range(2..=8),
        };
        let mut world = random_scene(n, 100 + u64::from(w));
        if w == 0 {
            for pose in &mut world.poses {
                for c in &mut pose.position[..3] {
                    *c *= 0.05;
                }
            }
        }
        firsts.push(scene.shapes.len());
        for shape in &mut world.shapes {
            shape.flags |= w << tumble_gpu::layout::BODY_WORLD_SHIFT;
        }
        scene.poses.extend(world.poses);
        scene.velocities.extend(world.velocities);
        scene.shapes.extend(world.shapes);
    }
    firsts.push(scene.shapes.len());
    let mut gpu = collision(&ctx, &scene, CollisionConfig::default());
    assert_eq!(gpu.sorts_by_world(), (true, true), "not sorted by world");
    let (snap, aabbs) = step_pairs_and_aabbs(&mut gpu);
    let statics = static_flags(&scene);
    let mut want = vec![];
    for w in firsts.windows(2) {
        let (first, end) = (w[0], w[1]);
        let alone =
            tumble_broad::sweep_and_prune_filtered(&aabbs[first..end], &statics[first..end])
                .unwrap();
        if first == 0 {
            assert!(alone.len() > 900, "world 0 has only {} pairs", alone.len());
        }
        want.extend(
            alone
                .into_iter()
                .map(|(a, b)| (a + first as u32, b + first as u32)),
        );
    }
    assert_eq!(snap.pairs.len(), want.len());
    assert!(
        snap.pairs == want,
        "the GPU's pair list differs from the worlds' CPU pairs"
    );
    // The CPU twin of the pair sort by world puts the same pairs, shuffled, back in order.
    let mut shuffled = want.clone();
    for i in (1..shuffled.len()).rev() {
        shuffled.swap(i, rng.random_range(0..=i));
    }
    let (a, b): (Vec<u32>, Vec<u32>) = shuffled.into_iter().unzip();
    let world_of = |body: u32| firsts.iter().filter(|&&f| f as u32 <= body).count() as u32 - 1;
    let (a, b) = sort_world_pairs_cpu(&a, &b, world_of);
    assert!(
        a.into_iter().zip(b).eq(want),
        "the CPU twin's order differs"
    );
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
        .read_buffer::<GpuContact>(gpu.contacts(), 0, snap.contacts.len() as u64)
        .unwrap();
    let mut want = snap.contacts.clone();
    scatter_impulses_cpu(&snap.touching, &impulses, &mut want);
    assert_eq!(per_pair, want);
    // A wrong length is refused, naming it.
    let err = gpu.store_touching_impulses(&impulses[1..]).unwrap_err();
    assert!(err.to_string().contains("impulses.len()"), "{err}");
}
