//! The GPU sorts on their own against their CPU twins: the radix sort (4-bit and wider
//! digits, stable), the one-workgroup rank sort of short lists, and the body sort one
//! workgroup per world; each must give the radix sort's order bit for bit, since the broad
//! phase's sweep and the narrow phase read the result as the order of the whole list. The
//! sorts inside a collision step are checked in `gpu_collision.rs`.
//!
//! Runs on any adapter (lavapipe in CI, with `TUMBLE_REQUIRE_GPU=1` so a missing adapter
//! fails); without one and without that variable, each test prints "skipped" and passes.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_gpu::kernels::{
    radix_sort::{RadixBuffers, RadixSort, radix_sort_cpu, result_copy},
    rank_sort::{
        RANK_SORT, RANK_SORT_CAPACITY, SORT_WORLD_BODIES, rank_sort_cpu, sort_world_bodies_cpu,
        world_body_starts,
    },
    write_sort_keys::sweep_key,
};
use tumble_gpu::layout::WorkList;
use tumble_gpu::{GpuContext, StageTimer};

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
