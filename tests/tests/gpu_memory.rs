//! GPU memory per body of a `Backend::Gpu` world: the buffers the pair-slot sizing formula
//! calls for and nothing more (docs/gpu.md, "Memory per body").
//!
//! Most of the memory is sized by the pair capacity, `CollisionConfig::pairs_per_body` slots
//! per body; the bound below adds up, from the engine's own struct sizes, every buffer sized
//! by it (with the copies the facade's step check keeps) and allows a fixed amount per body
//! for the per-body buffers. With the 600-cube pool below the bound leaves about 57 bytes per
//! body of room: it fails when a buffer of 8 bytes or more per pair slot is added or comes
//! back (the dense touching list of a readback was 248 bytes per slot and as much again in
//! the check's copy), when a per-slot buffer grows by as much, when the capacity is sized
//! above the formula, or when the per-body buffers grow by more than that room.
//!
//! Needs a GPU (or lavapipe): without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.

use std::mem::size_of;

use tumble::prelude::*;
use tumble::scenes;
use tumble_gpu::CollisionConfig;
use tumble_gpu::MAX_MANIFOLD_POINTS;
use tumble_gpu::layout::{GpuContact, GpuLocalManifold, GpuManifold};
use tumble_gpu::solver::layout::{ColorSlot, GpuConstraint, GpuTilt};

/// Bytes per pair slot of the buffers sized by the pair capacity, as `ensure_pair_buffers`
/// (collision) and `GpuSolver::ensure` (solver) size them.
fn bytes_per_pair_slot() -> u64 {
    let size = |bytes: usize| bytes as u64;
    let u32_bytes = size(size_of::<u32>());
    // Per step parity: the sorted pair (a, b), the manifold, its points and its local copy.
    let parity = 2 * u32_bytes
        + size(size_of::<GpuManifold>())
        + u64::from(MAX_MANIFOLD_POINTS) * size(size_of::<GpuContact>())
        + size(size_of::<GpuLocalManifold>());
    // The pair sort's scratch (a, b; one for both parities) and `previous_index` (scratch of
    // one step: the check does not copy it).
    let collision = 2 * parity + 2 * u32_bytes + u32_bytes;
    // The constraint store, the tilts and colors in two parities, the coloring's two scratch
    // words, the color sort's keys and values (two copies each) and the check's copy of the
    // values.
    let solver = size(size_of::<GpuConstraint>())
        + 2 * size(size_of::<GpuTilt>())
        + 2 * size(size_of::<ColorSlot>())
        + 2 * u32_bytes
        + 4 * u32_bytes
        + 2 * u32_bytes;
    collision + solver
}

/// Bytes per body allowed for the buffers sized by the body count, with the check's copies:
/// three 96-byte body arrays (the world's, the solver's, the sleep stage's awake bodies) and
/// their copies are 576; the coloring's (body, color) marks 100; poses, velocities, AABBs,
/// shapes and groups and their copies, the sweep boxes, the body sort and the sleep stage's
/// labels and timers with their copies about 345 (1,021 measured on lavapipe).
const PER_BODY_ALLOWANCE: u64 = 1_050;

/// Fixed-size buffers (parameter blocks, per-color tallies, the long-box list, sort tiles of
/// a small scene): about 16 KiB measured.
const FIXED_ALLOWANCE: u64 = 32 * 1024;

#[test]
fn a_gpu_pools_memory_per_body_stays_within_its_pair_slot_sizing() {
    // A 600-cube pool: 8 slots per body (4,840) is above the 4,096-slot minimum, so the
    // formula, not the floor, sizes the pair buffers.
    let scene = scenes::pool(600);
    let config = WorldConfig {
        backend: Backend::Gpu,
        ..Default::default()
    };
    let mut world = match World::from_scene(&scene, config) {
        Ok((world, _)) => world,
        Err(e @ tumble::Error::BackendUnavailable { .. })
            if std::env::var("TUMBLE_REQUIRE_GPU").as_deref() != Ok("1") =>
        {
            eprintln!("##### skipped: no GPU adapter ({e}) #####");
            return;
        }
        Err(e) => panic!("{e}"),
    };
    for _ in 0..3 {
        world.step().unwrap();
    }
    let bodies = scene.bodies.len() as u64;
    let pairs_per_body = u64::from(CollisionConfig::default().pairs_per_body);
    assert!(bodies * pairs_per_body > u64::from(CollisionConfig::default().min_pair_capacity));

    let sizes = world.device_buffer_sizes();
    let total = world.device_buffer_bytes();
    assert_eq!(sizes.iter().map(|s| s.2).sum::<u64>(), total);
    // The dense touching list is a readback's; the step never writes it.
    let touching: Vec<_> = sizes.iter().filter(|s| s.1.contains("touching")).collect();
    assert!(touching.is_empty(), "{touching:?}");

    let per_slot = bytes_per_pair_slot();
    let bound = bodies * (pairs_per_body * per_slot + PER_BODY_ALLOWANCE) + FIXED_ALLOWANCE;
    // The pair buffers alone, at the formula's size: the world cannot be below them, or the
    // bound counts buffers the engine no longer has (update the formula with it).
    let floor = bodies * pairs_per_body * per_slot;
    println!(
        "{bodies} bodies: {total} bytes ({} per body); pair slots {per_slot} bytes each; \
         bound {bound}, floor {floor}",
        total / bodies
    );
    assert!(total <= bound, "{total} bytes > {bound}: {sizes:?}");
    assert!(total >= floor, "{total} bytes < {floor}: {sizes:?}");
}
