//! Golden determinism hashes: every body's pose after 500 steps of five scenes (the pyramid of
//! 12, the wall of 10 x 10, the 20 dominoes, a cube sliding down a 30 degree ramp with friction
//! 0.3, and a plank ten times wider than the four cubes it rests on), hashed bit by bit and
//! compared with a committed value per scene.
//!
//! This is the guard for any rewrite of the step (a new backend layer, a faster solver, new
//! kernels): a change that moves a single bit of a single pose fails here. A committed hash
//! changes only in a commit that says why the results changed (docs/testing.md keeps the list).
//!
//! - CPU: the same hash with 1 and 2 rayon threads and with as many as the machine has, since a
//!   result that depends on the thread count would make every CPU number in the docs
//!   unreproducible; that hash must equal the committed one.
//! - GPU: on an adapter with committed hashes, one run of every scene must give the committed
//!   hash: a hash recorded by an earlier process is a stronger repeatability check than a second
//!   run in this one, and it halves the test's time on the software driver CI uses (a wide-path
//!   step of the packed pyramid of 12 takes about half a second there). On an adapter without
//!   committed hashes every scene runs twice and the two hashes must match. Hashes are keyed by
//!   the adapter name, which for
//!   the software Vulkan driver CI uses (lavapipe) carries its SIMD width ("llvmpipe (LLVM
//!   15.0.6, 256 bits)"), since a different JIT target can legally round differently. On any
//!   other adapter the test prints a line to add to [`GPU_GOLDEN`] to record its hashes.
//!
//! To print the current hashes: `cargo test -p tumble-tests --test golden_hash -- --nocapture`.

use tumble::{Backend, EffectOverrides, World, WorldConfig};
use tumble_gpu::GpuContext;
use tumble_scenes::{Scene, dominoes, friction_ramp, pyramid, wall, wide_on_small};

/// Steps per scene: 8.3 s at 60 Hz. Past the dominoes' whole chain and the piles' settling, and
/// long enough for the ramp's cube (1.5 m/s^2 down the slope) to slide the 15 m to the ramp's
/// lower end (about 4.5 s) and fall off it: a contact that slides, tips over an edge and vanishes.
const STEPS: usize = 500;

/// The scenes hashed, by name, with their committed CPU hash.
const CPU_GOLDEN: [(&str, u64); 5] = [
    ("pyramid_12", 0xf97a_775a_ed71_8d89),
    ("wall_10x10", 0x1b68_c0a9_07dc_dabb),
    ("dominoes_20", 0x2c39_23b2_fe9b_5e3a),
    ("friction_ramp_30deg_mu0.3", 0xdf1f_acaa_ee3d_7ec0),
    ("wide_on_small", 0x61fd_c173_daf7_4738),
];

/// Committed GPU hashes, keyed by the adapter name (which, for lavapipe, includes the JIT's
/// vector width). Same scene order as [`CPU_GOLDEN`].
const GPU_GOLDEN: &[(&str, [u64; 5])] = &[
    (
        "llvmpipe (LLVM 15.0.6, 256 bits)",
        [
            0x6bee_c7c1_8038_8ca2,
            0x44de_4e79_8c5b_194e,
            0x4dda_0636_9011_f1b8,
            0xc5d8_3585_7cc5_19da,
            0xc808_e5cc_07fc_cb5b,
        ],
    ),
    // Vulkan, driver 580.159.04, recorded with contact recycling on the GPU (docs/testing.md).
    // The H200's values from before recycling are out; until they are recorded again an H200
    // runs each scene twice and checks that the two runs agree.
    (
        "NVIDIA H100 80GB HBM3",
        [
            0xc33c_5317_dd00_bf07,
            0x5dc7_d7ff_04d2_dd7a,
            0x8301_9039_b6d4_192e,
            0xabd9_53f9_dd62_07c8,
            0xd3ad_c8ff_d31b_d27a,
        ],
    ),
];

fn scenes() -> Vec<Scene> {
    vec![
        pyramid(12),
        wall(10, 10),
        dominoes(20),
        // tan 30 degrees = 0.577 > 0.3: the cube slides, under kinetic friction throughout.
        friction_ramp(30.0, 0.3),
        // Mixed sizes and masses: a plank 100 times heavier than each of its supports.
        wide_on_small(),
    ]
}

/// FNV-1a over the bits of every coordinate of every pose (position, then rotation
/// quaternion), in body order. Any single-bit change in any pose changes the hash.
fn pose_hash(world: &World) -> u64 {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let mut hash = OFFSET;
    for &h in world.handles() {
        let pose = world.pose(h).expect("a live handle");
        let q = pose.rotation.quaternion();
        let coords = pose
            .translation
            .vector
            .iter()
            .copied()
            .chain([q.i, q.j, q.k, q.w]);
        for c in coords {
            for byte in c.to_bits().to_le_bytes() {
                hash ^= u64::from(byte);
                hash = hash.wrapping_mul(PRIME);
            }
        }
    }
    hash
}

/// Runs `scene` for [`STEPS`] steps on `backend` with the default solver and returns the hash.
/// The scene must actually move: a hash of a world that never stepped would match forever.
fn run(scene: &Scene, backend: Backend) -> u64 {
    let (mut world, handles) = World::from_scene(
        scene,
        WorldConfig {
            backend,
            // The committed hashes guard the step's arithmetic with every body integrated;
            // sleep has its own tests (sleep.rs, gpu_sleep).
            effects: EffectOverrides::NO_SLEEP,
            ..Default::default()
        },
    )
    .expect("the scene builds");
    let start = pose_hash(&world);
    for _ in 0..STEPS {
        world.step().expect("the step runs");
    }
    let end = pose_hash(&world);
    assert_ne!(start, end, "{}: no body moved in {STEPS} steps", scene.name);
    for &h in &handles {
        let p = world.pose(h).unwrap();
        assert!(
            p.translation.vector.iter().all(|c| c.is_finite()),
            "{}: non-finite pose {p:?}",
            scene.name
        );
    }
    end
}

fn run_with_threads(scene: &Scene, threads: usize) -> u64 {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(|| run(scene, Backend::Cpu))
}

/// The rayon pool sizes checked: 1, 2 and every core the machine has (once each).
fn thread_counts() -> Vec<usize> {
    let all = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut counts = vec![1, 2, all];
    counts.sort_unstable();
    counts.dedup();
    counts
}

#[test]
fn cpu_hashes_match_the_committed_ones_at_every_thread_count() {
    let counts = thread_counts();
    let mut failures = Vec::new();
    for (scene, (name, golden)) in scenes().iter().zip(CPU_GOLDEN) {
        assert_eq!(scene.name, name, "scene order");
        let hashes: Vec<u64> = counts
            .iter()
            .map(|&threads| run_with_threads(scene, threads))
            .collect();
        println!("{name}: CPU hashes at {counts:?} threads: {hashes:#018x?}");
        assert!(
            hashes.iter().all(|&h| h == hashes[0]),
            "{name}: the CPU result depends on the thread count ({counts:?}): {hashes:#018x?}"
        );
        if hashes[0] != golden {
            failures.push(format!(
                "{name}: {:#018x} (committed {golden:#018x})",
                hashes[0]
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "CPU results changed; update CPU_GOLDEN only in a commit that says why: {failures:?}"
    );
}

#[test]
fn gpu_hashes_repeat_and_match_the_committed_ones_of_the_adapter() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let adapter = ctx.info.name.clone();
    let golden = GPU_GOLDEN
        .iter()
        .find(|(name, _)| *name == adapter)
        .map(|(_, hashes)| *hashes);
    let mut hashes = Vec::new();
    let mut failures = Vec::new();
    for (k, scene) in scenes().iter().enumerate() {
        assert_eq!(scene.name, CPU_GOLDEN[k].0, "scene order");
        let first = run(scene, Backend::Gpu);
        println!("{}: GPU hash on {adapter}: {first:#018x}", scene.name);
        match golden {
            Some(golden) if first != golden[k] => failures.push(format!(
                "{}: {first:#018x} (committed {:#018x})",
                scene.name, golden[k]
            )),
            Some(_) => {}
            None => {
                let second = run(scene, Backend::Gpu);
                assert_eq!(
                    first, second,
                    "{}: two GPU runs on {adapter} in one process differ",
                    scene.name
                );
            }
        }
        hashes.push(first);
    }
    // The line that records this adapter's hashes in GPU_GOLDEN.
    let entry = hashes
        .iter()
        .map(|h| format!("{h:#018x}"))
        .collect::<Vec<_>>()
        .join(", ");
    println!("GPU_GOLDEN entry: ({adapter:?}, [{entry}]),");
    if golden.is_none() {
        eprintln!(
            "##### no committed GPU hashes for adapter {adapter:?}: run-to-run only; to record \
             them add to GPU_GOLDEN: ({adapter:?}, [{entry}]) #####"
        );
    }
    assert!(
        failures.is_empty(),
        "GPU results on {adapter} changed; update GPU_GOLDEN only in a commit that says why: {failures:?}"
    );
}
