//! The GPU broad phase with long boxes (floors, walls, planks spanning a pile): they are
//! paired apart from the sweep (`shaders/common/sweep.wgsl`), and the pair list must still
//! be exactly `tumble_broad`'s on the GPU's own AABBs, with few long boxes (listed) and with
//! more than the list holds (swept as any box).
//!
//! Runs on any adapter (lavapipe in CI, with `TUMBLE_REQUIRE_GPU=1` so a missing adapter
//! fails); without one and without that variable, the test prints "skipped" and passes.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Cuboid, Pose, Vec3};
use tumble_gpu::collision::CollisionConfig;
use tumble_gpu::constants::MAX_LONG_BOXES;
use tumble_gpu::kernels::sweep_pairs::long_extent;
use tumble_gpu::layout::{GpuPose, GpuShape, GpuVelocity};
use tumble_gpu::{GpuCollision, GpuContext};
use tumble_tests::gpu_scene::step_pairs_and_aabbs;

/// Side of the square the cubes stand on, m.
const SIDE: f32 = 30.0;

/// `cubes` cubes of 0.3 to 0.6 m scattered over a 30 m square in three loose layers on a
/// 100 m static floor, and `planks` long boxes 24 m long across the square at several heights
/// and headings (every third static), some crossing each other.
fn scene(
    cubes: usize,
    planks: usize,
    seed: u64,
) -> (Vec<GpuPose>, Vec<GpuVelocity>, Vec<GpuShape>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut poses = Vec::new();
    let mut shapes = Vec::new();
    let mut add = |half: Vec3, pose: Pose, is_static: bool| {
        poses.push(GpuPose::from_pose(&pose));
        shapes.push(GpuShape::cuboid(&Cuboid::new(half), is_static));
    };
    add(
        Vec3::new(50.0, 0.5, 50.0),
        Pose::translation(SIDE / 2.0, -0.5, SIDE / 2.0),
        true,
    );
    for _ in 0..cubes {
        let h = rng.random_range(0.15..0.3);
        let layer = rng.random_range(0..3) as f32;
        let pose = Pose::new(
            Vec3::new(
                rng.random_range(0.0..SIDE),
                h + 0.6 * layer,
                rng.random_range(0.0..SIDE),
            ),
            Vec3::new(0.0, rng.random_range(0.0..1.5), 0.0),
        );
        add(Vec3::repeat(h), pose, false);
    }
    for k in 0..planks {
        let heading = rng.random_range(-0.6..0.6) + if k % 2 == 0 { 0.0 } else { 1.57 };
        let pose = Pose::new(
            Vec3::new(SIDE / 2.0, rng.random_range(0.2..1.6), SIDE / 2.0),
            Vec3::new(0.0, heading, 0.0),
        );
        add(Vec3::new(12.0, 0.1, 0.4), pose, k % 3 == 0);
    }
    let velocities = vec![GpuVelocity::new(Vec3::zeros(), Vec3::zeros()); poses.len()];
    (poses, velocities, shapes)
}

fn pairs_equal_cpu(ctx: &GpuContext, cubes: usize, planks: usize, seed: u64) {
    let (poses, velocities, shapes) = scene(cubes, planks, seed);
    // The floor (100 m) and the planks (24 m) are long: past 16 cube diameters (at most
    // 16 x 1.04 m); no cube is.
    let extent = long_extent(&shapes);
    assert!(extent < 24.0 && extent > 1.04, "long extent {extent} m");
    let mut gpu = GpuCollision::new(ctx, CollisionConfig::default()).unwrap();
    gpu.set_bodies(&poses, &velocities, &shapes).unwrap();
    let (snap, aabbs) = step_pairs_and_aabbs(&mut gpu);
    let statics: Vec<bool> = shapes.iter().map(GpuShape::is_static).collect();
    let cpu = tumble_broad::sweep_and_prune_filtered(&aabbs, &statics).unwrap();
    // Every cube of the bottom layer touches the floor, and each plank meets cubes and other
    // planks: pairs with a long box must be there to find.
    let long = 1 + planks as u32;
    let first_plank = 1 + cubes as u32;
    let with_long = cpu
        .iter()
        .filter(|&&(a, b)| a == 0 || b >= first_plank || a >= first_plank)
        .count();
    assert!(with_long > cubes / 4, "{with_long} pairs with a long box");
    assert_eq!(
        snap.pairs.len(),
        cpu.len(),
        "{long} long boxes: pair counts differ"
    );
    assert!(snap.pairs == cpu, "{long} long boxes: pair lists differ");
}

#[test]
fn long_boxes_pair_exactly_as_the_cpu_sweep_listed_or_not() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // A floor and 6 planks: listed and paired apart. Then a floor and MAX_LONG_BOXES planks:
    // 65 long boxes, more than the list holds, so the sweep pairs them.
    pairs_equal_cpu(&ctx, 3000, 6, 1);
    pairs_equal_cpu(&ctx, 3000, MAX_LONG_BOXES as usize, 2);
}

/// Collision groups in the GPU's pair kernels: the scattered cubes and planks with seeded
/// groups (one of three memberships, a random filter of them), so that about half of the
/// overlapping pairs are refused, among them pairs with the floor and planks (long boxes,
/// paired by `long_pairs`) and between cubes (paired by `sweep_pairs`). The GPU's pair list
/// must be exactly the CPU grid's grouped list on the GPU's own AABBs: a kernel that ignored
/// the groups, or tested them from one side only, keeps pairs the CPU refuses.
#[test]
fn collision_groups_leave_out_exactly_the_refused_pairs() {
    use tumble_gpu::layout::GpuCollisionGroups;
    use tumble_solver::CollisionGroups;
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let (poses, velocities, shapes) = scene(3000, 6, 3);
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let groups: Vec<CollisionGroups> = (0..shapes.len())
        .map(|_| CollisionGroups::new(1 << rng.random_range(0..3), rng.random_range(0..8)))
        .collect();
    let mut gpu = GpuCollision::new(&ctx, CollisionConfig::default()).unwrap();
    gpu.set_bodies(&poses, &velocities, &shapes).unwrap();
    let uploaded: Vec<GpuCollisionGroups> =
        groups.iter().map(|&g| GpuCollisionGroups::of(g)).collect();
    gpu.set_groups(0, &uploaded).unwrap();
    let (snap, aabbs) = step_pairs_and_aabbs(&mut gpu);
    let statics: Vec<bool> = shapes.iter().map(GpuShape::is_static).collect();
    let all = tumble_broad::broad_phase_pairs_filtered(&aabbs, &statics).unwrap();
    let cpu = tumble_broad::broad_phase_pairs_grouped(&aabbs, &statics, &groups).unwrap();
    let long_pairs = |pairs: &[(u32, u32)]| pairs.iter().filter(|p| p.0 == 0 || p.1 > 3000).count();
    assert!(
        cpu.len() < all.len() * 3 / 4
            && long_pairs(&cpu) > 0
            && long_pairs(&cpu) < long_pairs(&all),
        "the groups must refuse pairs of both kinds: {} of {} kept, {} of {} with long boxes",
        cpu.len(),
        all.len(),
        long_pairs(&cpu),
        long_pairs(&all)
    );
    assert_eq!(snap.pairs.len(), cpu.len(), "pair counts differ");
    assert!(snap.pairs == cpu, "pair lists differ");
    // Back to every group: the full list again.
    gpu.set_groups(0, &vec![GpuCollisionGroups::ALL; shapes.len()])
        .unwrap();
    let (snap, _) = step_pairs_and_aabbs(&mut gpu);
    assert!(
        snap.pairs == all,
        "with every group, the static filter's list"
    );
}
