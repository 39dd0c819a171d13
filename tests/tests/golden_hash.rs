//! Golden determinism hashes: every body's pose after 300 steps of the pyramid of 12, the wall
//! and the dominoes, hashed bit by bit and compared with a committed value.
//!
//! This is the guard for any rewrite of the step (a new backend layer, a faster solver, new
//! kernels): a change that moves a single bit of a single pose fails here. A committed hash
//! changes only in a commit that says why the results changed.
//!
//! - CPU: the same hash with 1, 2 and 3 rayon threads, since a result that depends on the
//!   thread count would make every CPU number in the docs unreproducible.
//! - GPU: one hash per adapter. The software Vulkan driver CI uses (lavapipe) has a committed
//!   hash keyed by its adapter name, which carries its SIMD width ("llvmpipe (LLVM 15.0.6, 256
//!   bits)"), since a different JIT target can legally round differently. On any other adapter
//!   the hashes are printed and two runs of the dominoes must agree (`gpu_determinism.rs`
//!   covers run-to-run equality at length).
//!
//! To print the current hashes: `cargo test -p tumble-tests --test golden_hash -- --nocapture`.

use tumble::{Backend, World, WorldConfig};
use tumble_gpu::GpuContext;
use tumble_scenes::{Scene, dominoes, pyramid, wall};

/// Steps per scene: 5 s at 60 Hz, past the dominoes' whole chain and the piles' settling.
const STEPS: usize = 300;

/// The scenes hashed, by name, with their committed CPU hash.
const CPU_GOLDEN: [(&str, u64); 3] = [
    ("pyramid_12", 0xcb64_53e0_864f_87a9),
    ("wall_10x10", 0x0bf2_1cb3_7da9_9f57),
    ("dominoes_20", 0xc883_1629_e9b3_9efa),
];

/// Committed hashes on lavapipe, keyed by the adapter name (which includes the JIT's vector
/// width). Same scene order as [`CPU_GOLDEN`].
const LAVAPIPE_GOLDEN: &[(&str, [u64; 3])] = &[(
    "llvmpipe (LLVM 15.0.6, 256 bits)",
    [
        0x4a74_500d_11c1_af00,
        0xc46f_ff86_f61d_1ffe,
        0x7373_344b_3d97_d1d3,
    ],
)];

fn scenes() -> Vec<Scene> {
    vec![pyramid(12), wall(10, 10), dominoes(20)]
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

#[test]
fn cpu_hashes_match_the_committed_ones_at_every_thread_count() {
    let mut failures = Vec::new();
    for (scene, (name, golden)) in scenes().iter().zip(CPU_GOLDEN) {
        assert_eq!(scene.name, name, "scene order");
        let hashes: Vec<u64> = [1, 2, 3]
            .into_iter()
            .map(|threads| run_with_threads(scene, threads))
            .collect();
        println!("{name}: CPU hashes at 1, 2, 3 threads: {hashes:#018x?}");
        assert!(
            hashes.iter().all(|&h| h == hashes[0]),
            "{name}: the CPU result depends on the thread count: {hashes:#018x?}"
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
fn gpu_hashes_are_stable_and_match_lavapipes_committed_ones() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let adapter = ctx.info.name.clone();
    let golden = LAVAPIPE_GOLDEN
        .iter()
        .find(|(name, _)| *name == adapter)
        .map(|(_, hashes)| *hashes);
    let mut failures = Vec::new();
    for (k, scene) in scenes().iter().enumerate() {
        let hash = run(scene, Backend::Gpu);
        println!("{}: GPU hash on {adapter}: {hash:#018x}", scene.name);
        match golden {
            Some(golden) if hash != golden[k] => failures.push(format!(
                "{}: {hash:#018x} (committed {:#018x})",
                scene.name, golden[k]
            )),
            Some(_) => {}
            // No committed value: at least the run must repeat. The dominoes are the cheapest
            // scene with contacts that appear, slide and vanish.
            None if scene.name.starts_with("dominoes") => assert_eq!(
                hash,
                run(scene, Backend::Gpu),
                "{}: two GPU runs on {adapter} differ",
                scene.name
            ),
            None => {}
        }
    }
    if golden.is_none() {
        eprintln!("##### no committed GPU hash for adapter {adapter:?}: run-to-run only #####");
    }
    assert!(
        failures.is_empty(),
        "GPU results on {adapter} changed; update LAVAPIPE_GOLDEN only in a commit that says why: {failures:?}"
    );
}
