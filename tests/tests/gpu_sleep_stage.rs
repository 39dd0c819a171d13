//! The GPU sleep stage on synthetic contact graphs, against its CPU twins: the island search
//! equals `tumble_solver::island_search` bit for bit and union-find's islands on seeded random graphs (a
//! body touching 100 others and long shuffled chains among them), a chain too long for the
//! search's rounds is reported unfinished and puts no one to sleep, and the whole stage
//! (wakes, rest times, kinematic wakes, falling asleep) equals `tumble_solver::SleepLabels` step by step. The
//! whole-step tests are in `gpu_sleep/`.
//!
//! Needs a GPU (or lavapipe): without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Aabb, Cuboid, Point3, Pose, Vec3};
use tumble_gpu::collision::StepBuffers;
use tumble_gpu::layout::{GpuAabb, GpuManifold, GpuShape, GpuVelocity, WorkList};
use tumble_gpu::sleep::GpuSleep;
use tumble_gpu::sleep::constants::{AWAKE, ISLAND_ROUNDS};
use tumble_gpu::solver::convert::{gpu_body, gpu_shape};
use tumble_gpu::{GpuContext, StageTimer};
use tumble_solver::{Body, BodyKind, Islands, Material, TIME_TO_SLEEP};
use tumble_solver::{SleepLabels, SleepLink, island_search};

/// A body for the stage tests: a unit cube of `kind` at the origin (only its kind matters to
/// the stage).
fn body(kind: BodyKind) -> Body {
    Body::new(
        kind,
        Cuboid::new(Vec3::repeat(0.5)),
        Pose::identity(),
        1.0,
        Material::default(),
    )
    .unwrap()
}

/// One step's input to the sleep stage.
struct StageInput<'a> {
    /// The step's final velocities, (linear, angular).
    velocities: &'a [(Vec3, Vec3)],
    /// The step's manifolds.
    links: &'a [SleepLink],
    /// The step's AABBs.
    aabbs: &'a [Aabb],
    /// Bodies the host touched before the step.
    queued: &'a [u32],
}

/// `n` AABBs of zero size at the origin (for steps where no kinematic body moves).
fn points(n: usize) -> Vec<Aabb> {
    let origin = Point3::origin();
    vec![
        Aabb {
            min: origin,
            max: origin,
        };
        n
    ]
}

/// Runs the sleep stage once on the GPU. Returns the island labels, rest times, search
/// labels and whether the search finished.
fn run_stage(
    ctx: &GpuContext,
    sleep: &mut GpuSleep,
    bodies: &[Body],
    input: &StageInput<'_>,
) -> (Vec<u32>, Vec<f32>, Vec<u32>, bool) {
    let StageInput {
        velocities,
        links,
        aabbs,
        queued,
    } = *input;
    let n = bodies.len() as u64;
    let gpu_bodies: Vec<_> = bodies.iter().map(gpu_body).collect();
    let shapes: Vec<GpuShape> = bodies.iter().map(gpu_shape).collect();
    let v: Vec<GpuVelocity> = velocities
        .iter()
        .map(|(l, w)| GpuVelocity {
            linear: [l.x, l.y, l.z, 0.0],
            angular: [w.x, w.y, w.z, 0.0],
        })
        .collect();
    let manifolds: Vec<GpuManifold> = links
        .iter()
        .map(|l| GpuManifold {
            body_a: l.a,
            body_b: l.b,
            len: u32::from(l.touching),
            ..Default::default()
        })
        .collect();
    let boxes: Vec<GpuAabb> = aabbs
        .iter()
        .map(|b| GpuAabb {
            min: [b.min.x, b.min.y, b.min.z, 0.0],
            max: [b.max.x, b.max.y, b.max.z, 0.0],
        })
        .collect();
    let work = WorkList::for_count(links.len() as u32);
    let buffers = (
        ctx.storage_buffer("bodies", &gpu_bodies),
        ctx.storage_buffer("shapes", &shapes),
        ctx.storage_buffer("velocities", &v),
        ctx.storage_buffer("work", &[work]),
        ctx.storage_buffer("manifolds", &manifolds),
        ctx.storage_buffer("aabbs", &boxes),
        // The sleep stage reads neither poses nor contact points.
        ctx.storage_buffer("unused", &[0u32; 4]),
    );
    for &q in queued {
        sleep.queue_wake(q);
    }
    let mut encoder = ctx
        .device
        .create_command_encoder(&tumble_gpu::wgpu::CommandEncoderDescriptor { label: None });
    let mut timer = StageTimer::disabled(ctx);
    sleep.record_wake(&mut encoder, &mut timer, &buffers.0, &buffers.1);
    let inputs = StepBuffers {
        bodies: &buffers.0,
        shapes: &buffers.1,
        velocities: &buffers.2,
        contact_work: &buffers.3,
        manifolds: &buffers.4,
        aabbs: &buffers.5,
        poses: &buffers.6,
        contacts: &buffers.6,
    };
    sleep.record_update(&mut encoder, &mut timer, &inputs);
    ctx.queue.submit([encoder.finish()]);
    let island = ctx
        .read_buffer(sleep.island_labels().unwrap(), 0, n)
        .unwrap();
    let rest = ctx.read_buffer(sleep.rest_times().unwrap(), 0, n).unwrap();
    let labels = ctx
        .read_buffer(sleep.search_labels().unwrap(), 0, n)
        .unwrap();
    let unfinished: Vec<u32> = ctx
        .read_buffer(sleep.unfinished_flag().unwrap(), 0, 1)
        .unwrap();
    (island, rest, labels, unfinished[0] == 0)
}

/// Random kinds: mostly dynamic, with fixed and kinematic bodies that must not link islands.
fn random_kinds(rng: &mut ChaCha8Rng, n: usize) -> Vec<BodyKind> {
    (0..n)
        .map(|_| match rng.random_range(0..10) {
            0 => BodyKind::Fixed,
            1 => BodyKind::Kinematic,
            _ => BodyKind::Dynamic,
        })
        .collect()
}

/// A chain through all `n` bodies in a shuffled order: the longest path a graph of `n`
/// bodies can have, with labels scattered along it.
fn shuffled_chain(rng: &mut ChaCha8Rng, n: u32) -> Vec<(u32, u32)> {
    let mut order: Vec<u32> = (0..n).collect();
    for i in (1..order.len()).rev() {
        order.swap(i, rng.random_range(0..=i));
    }
    order.windows(2).map(|w| (w[0], w[1])).collect()
}

/// A chain whose labels alternate between the two ends (0, n-1, 1, n-2, ...), the order
/// that takes label propagation the most rounds among those tried.
fn zigzag_chain(n: u32) -> Vec<(u32, u32)> {
    let order: Vec<u32> = (0..n / 2).flat_map(|i| [i, n - 1 - i]).collect();
    order.windows(2).map(|w| (w[0], w[1])).collect()
}

/// The contact graphs of the twin test: sparse random graphs, a hub touching 100 others, long
/// shuffled chains, and grids of piles in scattered index order.
fn random_graph(rng: &mut ChaCha8Rng, family: usize) -> (usize, Vec<(u32, u32)>) {
    let n = rng.random_range(2..700u32);
    let links = match family {
        0 => (0..rng.random_range(0..2 * n))
            .map(|_| (rng.random_range(0..n), rng.random_range(0..n)))
            .collect(),
        1 => {
            let n = n.max(101);
            let hub = rng.random_range(0..n);
            let mut links: Vec<(u32, u32)> = (0..n)
                .filter(|&o| o != hub)
                .take(100)
                .map(|o| (hub.min(o), hub.max(o)))
                .collect();
            links.extend((0..n / 4).map(|_| (rng.random_range(0..n), rng.random_range(0..n))));
            return (n as usize, links);
        }
        2 => shuffled_chain(rng, n),
        _ => {
            let width = (n as f32).sqrt().max(1.0) as u32;
            let grid = (0..n)
                .flat_map(|i| [(i, i + 1), (i, i + width)])
                .filter(|&(a, b)| b < n && (b != a + 1 || b % width != 0));
            let mut order: Vec<u32> = (0..n).collect();
            for i in (1..order.len()).rev() {
                order.swap(i, rng.random_range(0..=i));
            }
            grid.map(|(a, b)| (order[a as usize], order[b as usize]))
                .collect()
        }
    };
    (n as usize, links)
}

/// Links as manifolds with points, pairs ordered as the narrow phase writes them (self-links,
/// which no manifold can be, dropped).
fn touching(links: &[(u32, u32)]) -> Vec<SleepLink> {
    links
        .iter()
        .filter(|(a, b)| a != b)
        .map(|&(a, b)| SleepLink {
            a: a.min(b),
            b: a.max(b),
            touching: true,
        })
        .collect()
}

/// Runs the search on the GPU with every body at rest for a whole TIME_TO_SLEEP step (so the
/// search runs, and every island sleeps when it finishes) and checks it against the twin:
/// exact labels and the same finished flag; when finished, the partition union-find gives,
/// with the same labels (each island's smallest body), and every dynamic body asleep under
/// its island's label.
fn check_search(ctx: &GpuContext, kinds: &[BodyKind], links: &[SleepLink], what: &str) -> bool {
    let bodies: Vec<Body> = kinds.iter().map(|&k| body(k)).collect();
    let still = (Vec3::zeros(), Vec3::zeros());
    let mut sleep = GpuSleep::new(ctx);
    let gpu: Vec<_> = bodies.iter().map(gpu_body).collect();
    sleep.enable(&gpu, TIME_TO_SLEEP).unwrap();
    let input = StageInput {
        velocities: &vec![still; bodies.len()],
        links,
        aabbs: &points(bodies.len()),
        queued: &[],
    };
    let (island, _, labels, finished) = run_stage(ctx, &mut sleep, &bodies, &input);
    let linkable: Vec<bool> = kinds.iter().map(|&k| k == BodyKind::Dynamic).collect();
    let pairs: Vec<(u32, u32)> = links
        .iter()
        .filter(|l| l.touching)
        .map(|l| (l.a, l.b))
        .collect();
    let twin = island_search(&linkable, &pairs, ISLAND_ROUNDS);
    assert_eq!(labels, twin.labels, "{what}: labels differ from the twin's");
    assert_eq!(finished, twin.finished, "{what}: finished flag");
    if finished {
        let islands = Islands::build(&linkable, pairs.iter().copied());
        assert_eq!(labels, islands.label, "{what}: not union-find's islands");
    }
    for (i, &dynamic) in linkable.iter().enumerate() {
        let expected = if finished && dynamic {
            labels[i]
        } else {
            AWAKE
        };
        assert_eq!(island[i], expected, "{what}: body {i}'s island label");
    }
    finished
}

#[test]
fn the_island_search_equals_its_cpu_twin_and_union_find() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    for case in 0..24 {
        let family = case % 4;
        let (n, links) = random_graph(&mut rng, family);
        let kinds = random_kinds(&mut rng, n);
        let finished = check_search(&ctx, &kinds, &touching(&links), &format!("case {case}"));
        // Every graph here is far shorter than 2^ISLAND_ROUNDS bodies: the search must
        // finish, or the rounds were miscounted.
        assert!(
            finished,
            "case {case} (family {family}, {n} bodies) did not finish"
        );
    }
    // Manifolds without points link nothing: a chain of them leaves every body alone.
    let mut links = touching(&shuffled_chain(&mut rng, 300));
    links.iter_mut().for_each(|l| l.touching = false);
    let kinds = vec![BodyKind::Dynamic; 300];
    check_search(&ctx, &kinds, &links, "pointless manifolds");
}

#[test]
fn a_chain_beyond_the_rounds_is_reported_unfinished_and_nothing_sleeps() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // A zigzag chain of 2^(ISLAND_ROUNDS + 1) bodies needs more rounds than there are (the
    // twin took 14 rounds at 16,000 bodies and one more per doubling): the flag must rise on
    // both sides, with the labels still equal bit for bit.
    let n = 1u32 << (ISLAND_ROUNDS + 1);
    let links = touching(&zigzag_chain(n));
    let kinds = vec![BodyKind::Dynamic; n as usize];
    // Every body rests a whole TIME_TO_SLEEP step, yet none may fall asleep (checked inside).
    assert!(!check_search(&ctx, &kinds, &links, "long zigzag"));
}

#[test]
fn the_sleep_stage_equals_its_cpu_twin_step_by_step() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    // 0.3 s steps: a body at rest reaches TIME_TO_SLEEP (0.5 s) on its second step, so within
    // six steps islands fall asleep, get touched, wake and fall asleep again.
    let dt = 0.3;
    for case in 0..6 {
        let n = rng.random_range(20..300usize);
        let kinds = random_kinds(&mut rng, n);
        let bodies: Vec<Body> = kinds.iter().map(|&k| body(k)).collect();
        let mut sleep = GpuSleep::new(&ctx);
        let gpu: Vec<_> = bodies.iter().map(gpu_body).collect();
        sleep.enable(&gpu, dt).unwrap();
        let mut twin = SleepLabels::new(n);
        let mut slept = 0;
        let mut woke = 0;
        let base: Vec<(u32, u32)> = (0..n)
            .map(|_| (rng.random_range(0..n as u32), rng.random_range(0..n as u32)))
            .collect();
        for step in 0..6 {
            // A moving quarter of the bodies (speeds far from the tolerances, so the GPU's
            // rounding cannot flip a rest test), a graph that keeps most links from step to
            // step, a few manifolds without points, and a few host wakes.
            let velocities: Vec<(Vec3, Vec3)> = (0..n)
                .map(|_| match rng.random_range(0..8) {
                    0 => (Vec3::new(0.0, 1.0, 0.0), Vec3::zeros()),
                    1 => (Vec3::zeros(), Vec3::new(0.0, 0.0, 1.0)),
                    _ => (Vec3::zeros(), Vec3::zeros()),
                })
                .collect();
            let mut links = touching(
                &base
                    .iter()
                    .copied()
                    .filter(|_| rng.random_bool(0.9))
                    .collect::<Vec<_>>(),
            );
            links
                .iter_mut()
                .for_each(|l| l.touching = rng.random_bool(0.9));
            let queued: Vec<u32> = (0..rng.random_range(0..3))
                .map(|_| rng.random_range(0..n as u32))
                .collect();
            // Boxes of 0.5 to 1 m scattered in a 10 m cube: a few overlap each, so moving
            // kinematic bodies reach some sleeping ones.
            let aabbs: Vec<Aabb> = (0..n)
                .map(|_| {
                    let c = Point3::from(Vec3::from_fn(|_, _| rng.random_range(0.0..10.0)));
                    let h = Vec3::repeat(rng.random_range(0.5..1.0));
                    Aabb {
                        min: c - h,
                        max: c + h,
                    }
                })
                .collect();
            let input = StageInput {
                velocities: &velocities,
                links: &links,
                aabbs: &aabbs,
                queued: &queued,
            };
            let (island, rest, ..) = run_stage(&ctx, &mut sleep, &bodies, &input);
            twin.wake_bodies(&queued);
            woke += twin.wake_islands().len();
            twin.update_rest(&kinds, &velocities, dt);
            twin.touch_sleepers(&links, &kinds, &velocities);
            twin.kinematic_wake(&kinds, &velocities, &aabbs);
            slept += twin.fall_asleep(&links, &kinds, ISLAND_ROUNDS).len();
            let what = format!("case {case} step {step}");
            assert_eq!(island, twin.island, "{what}: island labels");
            let bits = |r: &[f32]| r.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&rest), bits(&twin.rest_time), "{what}: rest times");
        }
        // The comparison covered both transitions, or it proved little.
        assert!(
            slept > 0 && woke > 0,
            "case {case}: slept {slept}, woke {woke}"
        );
    }
}
