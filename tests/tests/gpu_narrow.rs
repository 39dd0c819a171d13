//! The GPU narrow phase against its CPU twin on seeded pairs: the manifolds (the same
//! features and ids, positions and depths to 1e-4 of the box size, normals to 1e-3 rad), and
//! over two steps the feature hysteresis, pair matching and impulse carry (by id and by
//! position), and contact recycling against the CPU contact cache's rule.
//!
//! Runs on any adapter (lavapipe in CI, with `TUMBLE_REQUIRE_GPU=1` so a missing adapter
//! fails); without one and without that variable, each test prints "skipped" and passes.
// Tolerance checks are written `!(difference <= tolerance)` so that a NaN fails them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Pose, Rot, Vec3, nalgebra::Translation3};
use tumble_gpu::collision::CollisionConfig;
use tumble_gpu::kernels::{
    carry_impulses::{CarryHistory, carry_impulses_cpu},
    collide_cuboids::{kind_code, kind_from_code},
    match_pairs::match_pairs_cpu,
    recycle::recycle_gpu_pair,
};
use tumble_gpu::layout::{GpuContact, GpuPose};
use tumble_gpu::{GpuContext, MAX_MANIFOLD_POINTS, ReadbackRequest};
use tumble_tests::gpu_scene::{Scene, collision, contact_pairs};
use tumble_tests::scene_support::random_vec;

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
            let nudge = Rot::from_scaled_axis(random_vec(&mut rng, -1e-6..1e-6));
            *p = GpuPose::from_pose(&Pose::from_parts(pose.translation, nudge * pose.rotation));
        }
        let cpu = tumble_gpu::kernels::collide_gpu_pair(
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
        let cpu = tumble_gpu::kernels::collide_gpu_pair(
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

/// The first step of `gpu`, its manifolds in A's frame, and the points with impulses a solver
/// would have left (distinct per point, so a wrong match shows), stored for the next step.
fn first_step_with_impulses(
    gpu: &mut tumble_gpu::GpuCollision,
) -> (
    tumble_gpu::CollisionSnapshot,
    Vec<tumble_gpu::layout::GpuLocalManifold>,
    Vec<GpuContact>,
) {
    let first = gpu.step_and_read(ReadbackRequest::CONTACTS).unwrap();
    let locals = gpu.read_local_manifolds().unwrap();
    let mut stored = first.contacts.clone();
    for (i, c) in stored.iter_mut().enumerate() {
        c.normal_impulse = 1.0 + i as f32;
        c.friction_impulse = [i as f32, -(i as f32), 0.5, 0.0];
    }
    gpu.store_contacts(0, &stored).unwrap();
    (first, locals, stored)
}

/// The carry's CPU twin on the second step's manifolds: its points with the impulses it hands
/// out from the first step (`stored`, `first_locals`), and the frame-A records it keeps.
fn carried_by_twin(
    scene: &Scene,
    second: &tumble_gpu::CollisionSnapshot,
    first: &tumble_gpu::CollisionSnapshot,
    stored: &[GpuContact],
    first_locals: &[tumble_gpu::layout::GpuLocalManifold],
) -> (Vec<GpuContact>, Vec<tumble_gpu::layout::GpuLocalManifold>) {
    let mut want: Vec<GpuContact> = second.contacts.clone();
    for c in &mut want {
        c.normal_impulse = 0.0;
        c.friction_impulse = [0.0; 4];
    }
    let locals = carry_impulses_cpu(
        &scene.poses,
        &second.manifolds,
        &mut want,
        &CarryHistory {
            manifolds: &first.manifolds,
            contacts: stored,
            locals: first_locals,
        },
    );
    (want, locals)
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
    // Fresh manifolds only: a pair moved less than the recycle tolerance would keep last
    // step's (that rule has its own test below).
    let config = CollisionConfig {
        recycle_distance: 0.0,
        ..CollisionConfig::default()
    };
    let mut gpu = collision(&ctx, &scene, config);
    let (first, first_locals, stored) = first_step_with_impulses(&mut gpu);

    // Every second body moves a little: a millimetre and a quarter degree.
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for p in scene.poses.iter_mut().skip(1).step_by(2) {
        let pose = tumble_gpu::kernels::update_aabbs::pose_from_gpu(p);
        let nudge = Rot::from_scaled_axis(Vec3::new(
            rng.random_range(-4e-3..4e-3),
            rng.random_range(-4e-3..4e-3),
            0.0,
        ));
        let shift = random_vec(&mut rng, -1e-3..1e-3);
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
                let fresh = tumble_gpu::kernels::collide_gpu_pair(
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
    let (want, second_locals) = carried_by_twin(&scene, &second, &first, &stored, &first_locals);
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

/// Moves the bodies of `poses` for a second step: three designed pairs in four barely move
/// (each body up to 0.1 mm and 0.003 degrees: a slide far inside the 1 mm tolerance of boxes
/// whose half extents are at least 0.2 m, a turn far inside one degree); in the fourth, each
/// body moves up to 5 mm and a degree, well past both: most pairs recycle, some cannot.
fn mostly_barely_moved(poses: &mut [GpuPose]) {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    for (i, p) in poses.iter_mut().enumerate() {
        let (shift, turn) = if (i / 2) % 4 == 3 {
            (5e-3, 1.8e-2)
        } else {
            (1e-4, 5e-5)
        };
        let pose = tumble_gpu::kernels::update_aabbs::pose_from_gpu(p);
        let nudge = Rot::from_scaled_axis(random_vec(&mut rng, -turn..turn));
        let moved = random_vec(&mut rng, -shift..shift);
        *p = GpuPose::from_pose(&Pose::from_parts(
            Translation3::from(pose.translation.vector + moved),
            nudge * pose.rotation,
        ));
    }
}

#[test]
fn listing_the_fresh_pairs_of_a_workgroup_first_changes_no_bit() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // collide_cuboids may run the pairs of a workgroup that need the full test on its first
    // threads, in an order that varies from run to run; each result must still land at its own
    // pair's index, with the bits the pair's own thread would have given. A result written at
    // the listing position, a pair listed twice or left out, or a recycled thread that also ran
    // the full test would change a manifold or point here. Both settings run on any adapter
    // (the device picks one by default), on the mix of recycled and fresh pairs of the
    // recycling test.
    let second_step = |compact| {
        let mut scene = contact_pairs(3_000, 11);
        let config = CollisionConfig {
            compact_fresh_pairs: Some(compact),
            ..CollisionConfig::default()
        };
        let mut gpu = collision(&ctx, &scene, config);
        first_step_with_impulses(&mut gpu);
        mostly_barely_moved(&mut scene.poses);
        gpu.set_motion(&scene.poses, &scene.velocities).unwrap();
        gpu.step_and_read(ReadbackRequest::CONTACTS).unwrap()
    };
    let (each, listed) = (second_step(false), second_step(true));
    let recycled = listed.manifolds.iter().filter(|m| m.recycled != 0).count();
    let fresh = listed.manifolds.iter().filter(|m| m.recycled == 0).count();
    // Both kinds, in every workgroup of 256 pairs on average: otherwise the listing is trivial.
    assert!(
        recycled > 1_000 && fresh > 300,
        "{recycled} recycled, {fresh} fresh"
    );
    assert_eq!(listed.pairs, each.pairs);
    // Debug prints each float's shortest round-trip form, so equal text is equal bits.
    for (k, (a, b)) in listed.manifolds.iter().zip(&each.manifolds).enumerate() {
        assert_eq!(format!("{a:?}"), format!("{b:?}"), "manifold {k}");
    }
    for (i, (a, b)) in listed.contacts.iter().zip(&each.contacts).enumerate() {
        assert_eq!(format!("{a:?}"), format!("{b:?}"), "point {i}");
    }
    assert_eq!(listed.contacts.len(), each.contacts.len());
}

#[test]
fn recycled_manifolds_follow_the_cpu_contact_caches_rule_and_keep_their_impulses() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let mut scene = contact_pairs(3_000, 11);
    let config = CollisionConfig::default();
    assert!(config.recycle_distance > 0.0, "recycling is on by default");
    let mut gpu = collision(&ctx, &scene, config);
    let (first, first_locals, stored) = first_step_with_impulses(&mut gpu);

    mostly_barely_moved(&mut scene.poses);
    gpu.set_motion(&scene.poses, &scene.velocities).unwrap();
    let second = gpu.step_and_read(ReadbackRequest::CONTACTS).unwrap();
    let second_locals = gpu.read_local_manifolds().unwrap();

    let per = MAX_MANIFOLD_POINTS as usize;
    let (mut recycled, mut fresh, mut disagree) = (0usize, 0usize, Vec::new());
    for (k, &pair) in second.pairs.iter().enumerate() {
        let m = &second.manifolds[k];
        let prev = m.previous;
        if prev == tumble_gpu::constants::NO_PREVIOUS || first.manifolds[prev as usize].len == 0 {
            assert_eq!(
                m.recycled, 0,
                "pair {pair:?} recycled without a manifold to reuse"
            );
            continue;
        }
        let p = prev as usize;
        let old = &first.manifolds[p];
        let cpu = recycle_gpu_pair(
            &scene.poses,
            &scene.velocities,
            &scene.shapes,
            pair,
            (
                old,
                &first.contacts[p * per..(p + 1) * per],
                &first_locals[p],
            ),
            config.recycle_distance,
            config.margin,
            config.dt,
        );
        match (m.recycled != 0, cpu) {
            (true, Some(c)) => {
                recycled += 1;
                // The same points: ids, kind and feature are the old manifold's.
                let g = second.manifold(k).expect("a recycled manifold has points");
                assert_eq!((g.kind, g.feature, g.len), (c.kind, c.feature, c.len));
                let ids = |m: &tumble_geometry::Manifold| {
                    m.points().iter().map(|p| p.id).collect::<Vec<_>>()
                };
                assert_eq!(ids(&g), ids(&c), "pair {pair:?}");
                // The CPU carries the anchors to world space and subtracts there, the GPU in
                // A's frame: both round world coordinates of up to 45 m (f32 spacing 4e-6 m)
                // a few times, so positions and depths agree to 2e-5 m, a fiftieth of the
                // tolerance a point may slide.
                for (a, b) in g.points().iter().zip(c.points()) {
                    let dp = (a.position - b.position).norm();
                    let dd = (a.depth - b.depth).abs();
                    assert!(
                        !(dp > 2e-5) && !(dd > 2e-5),
                        "pair {pair:?}: {dp} m, depth {dd} m"
                    );
                }
                assert!(!((g.normal - c.normal).norm() > 1e-5), "pair {pair:?}");
                // Each point keeps its own impulse: ids and feature are unchanged, so the
                // carry matches every point to its old self.
                for i in 0..g.len as usize {
                    let (now, before) = (&second.contacts[k * per + i], &stored[p * per + i]);
                    assert_eq!(now.normal_impulse, before.normal_impulse, "pair {pair:?}");
                    assert_eq!(
                        now.friction_impulse, before.friction_impulse,
                        "pair {pair:?}"
                    );
                }
                // The anchors stay those of the manifold last computed.
                assert_eq!(second_locals[k], first_locals[p], "pair {pair:?}");
            }
            (false, None) => fresh += 1,
            (gpu_says, cpu) => disagree.push(format!(
                "pair {pair:?}: GPU recycled {gpu_says}, CPU {}",
                cpu.is_some()
            )),
        }
    }
    // The carry's CPU twin on the same manifolds (recycled ones included) hands out the same
    // impulses and keeps the same frame-A records for the recycled manifolds (copied, never
    // computed, so exactly).
    let (want, twin_locals) = carried_by_twin(&scene, &second, &first, &stored, &first_locals);
    assert_eq!(second.contacts, want);
    for (k, m) in second.manifolds.iter().enumerate() {
        if m.recycled != 0 {
            assert_eq!(second_locals[k], twin_locals[k], "slot {k}");
        }
    }
    eprintln!(
        "{recycled} recycled, {fresh} fresh, {} disagree",
        disagree.len()
    );
    // The two sides round differently, so a pair on the edge of a threshold may fall either
    // way; more than 1 % would be a different rule.
    assert!(
        disagree.len() * 100 <= recycled + fresh,
        "{} disagreements:\n{}",
        disagree.len(),
        disagree.join("\n")
    );
    // Both branches were exercised.
    assert!(
        recycled * 2 > recycled + fresh,
        "{recycled} recycled of {}",
        recycled + fresh
    );
    assert!(
        fresh * 10 > recycled + fresh,
        "{fresh} fresh of {}",
        recycled + fresh
    );
}
