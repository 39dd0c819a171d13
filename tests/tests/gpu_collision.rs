//! The GPU collision stages against their CPU twins on seeded random scenes: AABBs, sweep
//! axis, radix sort, the broad-phase pair list (exactly the CPU's), pair overflow and growth,
//! bad input, and the touching readback. The narrow phase's checks are in `gpu_narrow.rs`,
//! the long boxes of the broad phase in `gpu_broad_phase.rs`.
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
    radix_sort::{RadixBuffers, RadixSort, radix_sort_cpu, result_copy},
    rank_sort::{
        RANK_SORT, RANK_SORT_CAPACITY, SORT_WORLD_BODIES, rank_sort_cpu, sort_world_bodies_cpu,
        sort_world_pairs_cpu, world_body_starts,
    },
    update_aabbs::pose_from_gpu,
    velocity_from_gpu,
    write_sort_keys::{sweep_key, write_sort_keys_cpu},
};
use tumble_gpu::layout::{GpuContact, GpuPose, GpuShape, GpuVelocity, WorkList};
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

/// Runs the radix sort alone on `keys`/`values` with the count given on the GPU.
fn gpu_sort(
    ctx: &GpuContext,
    keys: &[u32],
    values: &[u32],
    sorts: &[(bool, u32)],
) -> (Vec<u32>, Vec<u32>) {
    gpu_sort_digits(ctx, RadixSort::new(ctx).unwrap(), keys, values, sorts)
}

/// [`gpu_sort`] with a given sort (digit width).
fn gpu_sort_digits(
    ctx: &GpuContext,
    sort: RadixSort,
    keys: &[u32],
    values: &[u32],
    sorts: &[(bool, u32)],
) -> (Vec<u32>, Vec<u32>) {
    let n = keys.len() as u32;
    let work = ctx.storage_buffer("work", &[WorkList::for_count(n)]);
    let k = [
        ctx.storage_buffer("k0", keys),
        ctx.storage_buffer("k1", keys),
    ];
    let v = [
        ctx.storage_buffer("v0", values),
        ctx.storage_buffer("v1", values),
    ];
    let tiles = ctx.storage_buffer("tiles", &vec![0u32; sort.tile_count_len(n) as usize]);
    let passes = sort.plan(sorts);
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

/// Runs the one-workgroup rank sort alone on `keys`/`values` (sorted in place).
fn gpu_rank_sort(ctx: &GpuContext, keys: &[u32], values: &[u32]) -> (Vec<u32>, Vec<u32>) {
    let n = keys.len() as u32;
    let work = ctx.storage_buffer("work", &[WorkList::for_count(n)]);
    let k = ctx.storage_buffer("keys", keys);
    let v = ctx.storage_buffer("values", values);
    let kernel = tumble_gpu::kernel::Kernel::new(ctx, &RANK_SORT).unwrap();
    // The kernel's bindings, by the names its shader gives them.
    let group = kernel.bind_named(ctx, |name| match name {
        "work" => &work,
        "keys" => &k,
        "values" => &v,
        _ => panic!("rank_sort has no binding {name}"),
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    {
        let mut timer = StageTimer::disabled(ctx);
        let mut pass = timer.begin_pass(&mut encoder, "rank sort");
        kernel.dispatch_workgroups(&mut pass, &group, 1, 1);
    }
    ctx.queue.submit([encoder.finish()]);
    (
        ctx.read_buffer(&k, 0, u64::from(n)).unwrap(),
        ctx.read_buffer(&v, 0, u64::from(n)).unwrap(),
    )
}

#[test]
fn rank_sort_is_the_radix_sorts_order_for_bodies_and_pairs() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    // The collision stage sorts up to RANK_SORT_CAPACITY bodies or pairs with it, and the
    // order decides the sweep's and the narrow phase's order, so it must be exactly the radix
    // sort's. Bodies: values are input positions, so (key, value) order is the stable order by
    // key. Lengths from one item to the capacity, keys from a range of 7 (ties everywhere: a
    // slot error shows as values out of input order), of 2^32 (extremes included) and one key.
    for (n, range) in [
        (1usize, 7u64),
        (2, 7),
        (255, 7),
        (257, 1 << 32),
        (777, 7),
        (RANK_SORT_CAPACITY as usize, 1 << 32),
        (RANK_SORT_CAPACITY as usize, 1),
    ] {
        let mut keys: Vec<u32> = (0..n).map(|_| rng.random_range(0..range) as u32).collect();
        if n > 2 && range > 7 {
            keys[0] = u32::MAX;
            keys[1] = 0;
        }
        let values: Vec<u32> = (0..n as u32).collect();
        let got = gpu_rank_sort(&ctx, &keys, &values);
        assert_eq!(
            got,
            radix_sort_cpu(&keys, &values, 32),
            "n = {n}, range {range}"
        );
    }
    // Pairs (a, b) of 60 bodies, distinct, in random order: the radix chain (by b, then
    // stably by a) gives (a, b) order, and so must the rank sort.
    let mut pairs: Vec<(u32, u32)> = (0..60u32)
        .flat_map(|a| (a + 1..60).map(move |b| (a, b)))
        .filter(|_| rng.random_bool(0.5))
        .take(RANK_SORT_CAPACITY as usize)
        .collect();
    for i in (1..pairs.len()).rev() {
        pairs.swap(i, rng.random_range(0..=i));
    }
    let (a, b): (Vec<u32>, Vec<u32>) = pairs.iter().copied().unzip();
    let radix = gpu_sort(&ctx, &a, &b, &[(false, 6), (true, 6)]);
    assert_eq!(gpu_rank_sort(&ctx, &a, &b), radix);
    assert_eq!(rank_sort_cpu(&a, &b), radix);
    // Repeated pairs with values out of order: key, then value, equal pairs in input order.
    let keys: Vec<u32> = (0..500).map(|_| rng.random_range(0..5)).collect();
    let values: Vec<u32> = (0..500).map(|_| rng.random_range(0..5)).collect();
    assert_eq!(
        gpu_rank_sort(&ctx, &keys, &values),
        rank_sort_cpu(&keys, &values)
    );
}

/// Runs `sort_world_bodies` alone on `keys`/`values` (sorted in place), world `w` being
/// `starts[w]..starts[w + 1]`.
fn gpu_world_sort(
    ctx: &GpuContext,
    keys: &[u32],
    values: &[u32],
    starts: &[u32],
) -> (Vec<u32>, Vec<u32>) {
    let n = keys.len() as u32;
    // The kernel's table: the world count, then the starts.
    let mut with_count = vec![starts.len() as u32 - 1];
    with_count.extend_from_slice(starts);
    let table = ctx.storage_buffer("world_body_starts", &with_count);
    let k = ctx.storage_buffer("keys", keys);
    let v = ctx.storage_buffer("values", values);
    let kernel = tumble_gpu::kernel::Kernel::new(ctx, &SORT_WORLD_BODIES).unwrap();
    let group = kernel.bind_named(ctx, |name| match name {
        "world_body_starts" => &table,
        "keys" => &k,
        "values" => &v,
        _ => panic!("sort_world_bodies has no binding {name}"),
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    {
        let mut timer = StageTimer::disabled(ctx);
        let mut pass = timer.begin_pass(&mut encoder, "world sort");
        kernel.dispatch_workgroups(&mut pass, &group, starts.len() as u32 - 1, 1);
    }
    ctx.queue.submit([encoder.finish()]);
    (
        ctx.read_buffer(&k, 0, u64::from(n)).unwrap(),
        ctx.read_buffer(&v, 0, u64::from(n)).unwrap(),
    )
}

#[test]
fn world_body_starts_lists_each_worlds_run_and_refuses_worlds_out_of_order() {
    // World w is starts[w]..starts[w + 1]; a world with no bodies is an empty run, and a world
    // index that goes back down means a world's bodies are not one run, which the sort by
    // world cannot handle (the step then sorts the whole list).
    assert_eq!(
        world_body_starts([0, 0, 1, 1, 1, 3]),
        Some(vec![0, 2, 5, 5, 6])
    );
    assert_eq!(world_body_starts([1, 1]), Some(vec![0, 0, 2]));
    assert_eq!(world_body_starts([]), Some(vec![0, 0]));
    assert_eq!(world_body_starts([0, 1, 0]), None);
}

#[test]
fn sort_by_world_is_the_radix_sorts_order_of_the_whole_list() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    // A step of several worlds sorts each world's bodies in its own workgroup. The sweep and
    // the narrow phase read the result as the order of the whole list, so it must be the radix
    // sort's stable order of every key, bit for bit. Worlds of 0 to RANK_SORT_CAPACITY bodies
    // (empty ones, one body, the largest the kernel takes), bounds from a range of 5 values
    // (ties everywhere: a slot error shows as bodies out of input order) or of any float, keys
    // led by the world as the broad phase writes them.
    let sizes = [
        3usize,
        0,
        1,
        21,
        RANK_SORT_CAPACITY as usize,
        0,
        300,
        2,
        21,
        64,
    ];
    let worlds: Vec<u32> = sizes
        .iter()
        .enumerate()
        .flat_map(|(w, &n)| std::iter::repeat_n(w as u32, n))
        .collect();
    let world_bits = u32::BITS - (sizes.len() as u32 - 1).leading_zeros();
    let starts = world_body_starts(worlds.iter().copied()).unwrap();
    for spread in [5.0f32, 1e6] {
        let keys: Vec<u32> = worlds
            .iter()
            .map(|&w| {
                let x = if spread < 10.0 {
                    rng.random_range(0..5) as f32
                } else {
                    rng.random_range(-spread..spread)
                };
                sweep_key(w, x, world_bits)
            })
            .collect();
        let values: Vec<u32> = (0..keys.len() as u32).collect();
        let whole = radix_sort_cpu(&keys, &values, 32);
        assert_eq!(
            sort_world_bodies_cpu(&keys, &values, &starts),
            whole,
            "CPU twin, spread {spread}"
        );
        assert_eq!(
            gpu_world_sort(&ctx, &keys, &values, &starts),
            whole,
            "GPU, spread {spread}"
        );
    }
}

#[test]
fn wide_digit_radix_sort_is_the_same_stable_sort() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    // The color sort's shape: 5-bit keys (colors, overflow, empty) in one 32-bucket pass,
    // 100,003 of them (a partial last tile). Few distinct keys over many items is where a
    // rank error within a tile would show as values out of their input order.
    let keys: Vec<u32> = (0..100_003).map(|_| rng.random_range(0..26)).collect();
    let values: Vec<u32> = (0..keys.len() as u32).collect();
    let five = RadixSort::with_digit_bits(&ctx, 5).unwrap();
    assert_eq!(
        five.plan(&[(true, 5)]).len(),
        1,
        "5 key bits are one 5-bit pass"
    );
    let got = gpu_sort_digits(&ctx, five, &keys, &values, &[(true, 5)]);
    assert_eq!(got, radix_sort_cpu(&keys, &values, 5));
    // Full 32-bit keys with 8-bit digits: four passes, the same order as 4-bit digits.
    let keys: Vec<u32> = (0..20_000).map(|_| rng.random()).collect();
    let values: Vec<u32> = (0..keys.len() as u32).collect();
    let eight = RadixSort::with_digit_bits(&ctx, 8).unwrap();
    let got = gpu_sort_digits(&ctx, eight, &keys, &values, &[(true, 32)]);
    assert_eq!(got, radix_sort_cpu(&keys, &values, 32));
    // A digit wider than the histogram's one bucket per thread is refused, not clamped.
    let err = RadixSort::with_digit_bits(&ctx, 9).unwrap_err().to_string();
    assert!(err.contains("digit_bits") && err.contains('9'), "{err}");
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
