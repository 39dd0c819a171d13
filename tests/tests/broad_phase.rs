//! The broad phase: the step's grid (`BroadPhase`) and the one-axis sweep kept beside it must
//! both return exactly the brute-force pair list, on random scenes of every size and on grids
//! of exactly touching boxes.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_broad::{
    BroadPhase, BroadPhaseError, SweepAndPrune, broad_phase_pairs, broad_phase_pairs_filtered,
    brute_force_pairs, brute_force_pairs_filtered, sweep_and_prune, sweep_and_prune_filtered,
    sweep_axis,
};
use tumble_geometry::nalgebra::{Translation3, UnitQuaternion};
use tumble_geometry::{Aabb, Cuboid, Point3, Pose, Vec3};
use tumble_tests::scene_support::random_vec;
use tumble_tests::scene_support::{resting_aabbs, sparse_boxes};

/// Rotated cuboids gathered around a few cluster centres, as piles in a game level are: many
/// boxes share the sweep window, the case that makes a sweep degrade.
fn clustered_boxes(n: usize, clusters: usize, seed: u64) -> Vec<Aabb> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let centres: Vec<Vec3> = (0..clusters)
        .map(|_| {
            Vec3::new(
                rng.random_range(-100.0..100.0),
                rng.random_range(0.0..20.0),
                rng.random_range(-100.0..100.0),
            )
        })
        .collect();
    (0..n)
        .map(|i| {
            let offset = random_vec(&mut rng, -4.0..4.0);
            let axis = random_vec(&mut rng, -1.0..1.0);
            let rot = UnitQuaternion::from_scaled_axis(axis * 3.0);
            let pose = Pose::from_parts(Translation3::from(centres[i % clusters] + offset), rot);
            let cuboid = Cuboid::new(random_vec(&mut rng, 0.1..0.6));
            cuboid.aabb(&pose, 0.0)
        })
        .collect()
}

/// `nx x ny x nz` cubes of side `side`, each exactly touching its 26 neighbours, starting at
/// `origin`. Coordinates are small multiples of a power of two, so `min` of one box equals
/// `max` of its neighbour bit for bit.
fn touching_grid(n: [usize; 3], side: f32, origin: [f32; 3]) -> Vec<Aabb> {
    let mut out = Vec::new();
    for i in 0..n[0] {
        for j in 0..n[1] {
            for k in 0..n[2] {
                let min = Point3::new(
                    origin[0] + i as f32 * side,
                    origin[1] + j as f32 * side,
                    origin[2] + k as f32 * side,
                );
                out.push(Aabb::new(min, min + Vec3::repeat(side)));
            }
        }
    }
    out
}

/// Pairs of cells of an `n` grid whose indices differ by at most one on every axis: per axis
/// there are `3 m - 2` ordered (cell, neighbour-or-self) choices, minus the cells paired with
/// themselves, halved for unordered pairs.
fn grid_pair_count(n: [usize; 3]) -> usize {
    let ordered: usize = n.iter().map(|&m| 3 * m - 2).product();
    (ordered - n.iter().product::<usize>()) / 2
}

fn assert_sorted_unique(pairs: &[(u32, u32)]) {
    assert!(
        pairs.iter().all(|&(i, j)| i < j),
        "every pair must have i < j"
    );
    assert!(
        pairs.windows(2).all(|w| w[0] < w[1]),
        "pairs must be strictly ascending (sorted, no duplicates)"
    );
}

fn assert_matches_brute_force(aabbs: &[Aabb]) -> usize {
    let expected = brute_force_pairs(aabbs);
    let got = sweep_and_prune(aabbs);
    assert_sorted_unique(&expected);
    assert_eq!(
        got.len(),
        expected.len(),
        "pair counts differ for {} boxes",
        aabbs.len()
    );
    assert_eq!(got, expected);
    // The grid, pair for pair and in the same order (the step consumes pairs in order).
    assert_eq!(broad_phase_pairs(aabbs), expected, "grid");
    expected.len()
}

#[test]
fn empty_and_single_box_have_no_pairs() {
    assert!(sweep_and_prune(&[]).is_empty());
    assert!(broad_phase_pairs(&[]).is_empty());
    let one = sparse_boxes(1, 10.0, 1);
    assert!(sweep_and_prune(&one).is_empty());
    assert!(broad_phase_pairs(&one).is_empty());
    assert!(brute_force_pairs(&one).is_empty());
}

#[test]
fn two_boxes_pair_exactly_when_they_overlap_or_touch() {
    let a = Aabb::new(Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 1.0, 1.0));
    for (dx, pairs) in [(0.5, 1), (1.0, 1), (1.0 + 1e-6, 0), (-1.0, 1), (-1.5, 0)] {
        let b = Aabb::new(
            a.min + Vec3::new(dx, 0.0, 0.0),
            a.max + Vec3::new(dx, 0.0, 0.0),
        );
        let got = sweep_and_prune(&[a, b]);
        assert_eq!(
            got.len(),
            pairs,
            "shift {dx}: touching (|dx| = 1) must pair"
        );
        assert_eq!(got, brute_force_pairs(&[a, b]));
        assert_eq!(broad_phase_pairs(&[a, b]), got);
        // The order of the input must not change the answer beyond relabelling.
        assert_eq!(sweep_and_prune(&[b, a]).len(), pairs);
    }
}

#[test]
fn random_sparse_scenes_match_brute_force() {
    // Density of about 0.3 boxes per unit volume: each box meets a handful of neighbours.
    for (n, seed) in [(2, 11), (1_000, 12), (20_000, 13)] {
        let extent = (n as f32 / 0.3).cbrt();
        let pairs = assert_matches_brute_force(&sparse_boxes(n, extent, seed));
        if n >= 1_000 {
            // A test scene with no pairs would prove nothing about the sweep.
            assert!(pairs > n / 10, "{n} boxes gave only {pairs} pairs");
        }
    }
}

#[test]
fn random_clustered_scenes_match_brute_force() {
    for (n, clusters, seed) in [(2, 1, 21), (1_000, 5, 22), (20_000, 40, 23)] {
        let pairs = assert_matches_brute_force(&clustered_boxes(n, clusters, seed));
        if n >= 1_000 {
            assert!(pairs > n, "{n} clustered boxes gave only {pairs} pairs");
        }
    }
}

#[test]
fn touching_grid_pairs_every_face_edge_and_corner_neighbour() {
    for (n, origin) in [
        ([6, 5, 4], [0.0, 0.0, 0.0]),
        ([12, 3, 7], [-3.0, 2.0, 5.5]),
        // Far from the origin the coordinates stay exact (multiples of 0.5 below 2^23).
        ([4, 4, 4], [4096.0, 0.0, -4096.0]),
    ] {
        let grid = touching_grid(n, 0.5, origin);
        let pairs = sweep_and_prune(&grid);
        assert_eq!(pairs.len(), grid_pair_count(n), "grid {n:?} at {origin:?}");
        assert_eq!(pairs, brute_force_pairs(&grid));
        assert_eq!(broad_phase_pairs(&grid), pairs, "grid broad phase");
        let index = |i: usize, j: usize, k: usize| (i * n[1] * n[2] + j * n[2] + k) as u32;
        // A face neighbour, an edge neighbour, a corner neighbour: all touch, all must pair.
        for (a, b) in [
            (index(0, 0, 0), index(1, 0, 0)),
            (index(0, 0, 0), index(1, 1, 0)),
            (index(0, 0, 0), index(1, 1, 1)),
            (index(1, 0, 1), index(0, 1, 2)),
        ] {
            let pair = (a.min(b), a.max(b));
            assert!(
                pairs.binary_search(&pair).is_ok(),
                "missing touching pair {pair:?}"
            );
        }
        // Two cells apart: a gap of one cube, never a pair.
        assert!(
            pairs
                .binary_search(&(index(0, 0, 0), index(2, 0, 0)))
                .is_err()
        );
    }
}

#[test]
fn identical_boxes_all_pair() {
    let b = Aabb::new(Point3::new(1.0, 2.0, 3.0), Point3::new(1.0, 2.0, 3.0));
    let n = 150;
    let pairs = sweep_and_prune(&vec![b; n]);
    // Zero-size boxes at one point still touch (closed intervals): every pair appears.
    assert_eq!(pairs.len(), n * (n - 1) / 2);
    assert_eq!(broad_phase_pairs(&vec![b; n]), pairs);
}

#[test]
fn sweep_axis_follows_the_largest_spread() {
    for axis in 0..3 {
        let boxes: Vec<Aabb> = (0..50)
            .map(|i| {
                let mut c = Vec3::new(0.1 * (i % 3) as f32, 0.2 * (i % 2) as f32, 0.0);
                c[axis] = i as f32 * 3.0;
                let p = Point3::from(c);
                Aabb::new(p, p + Vec3::repeat(1.0))
            })
            .collect();
        assert_eq!(sweep_axis(&boxes), axis);
        let mut sap = SweepAndPrune::new();
        let mut out = Vec::new();
        sap.find_pairs(&boxes, &mut out);
        assert_eq!(sap.last_axis(), axis);
        assert_eq!(out, brute_force_pairs(&boxes));
    }
}

#[test]
fn reused_buffers_give_the_same_answer_as_a_fresh_sweep() {
    let mut sap = SweepAndPrune::new();
    let mut out = vec![(7, 9)]; // stale content must be cleared
    for (n, seed) in [(3_000, 31), (50, 32), (0, 33), (2_000, 34)] {
        let boxes = clustered_boxes(n, 3, seed);
        sap.find_pairs(&boxes, &mut out);
        assert_eq!(out, sweep_and_prune(&boxes), "reuse after {n} boxes");
    }
    // The same for the grid, whose buffers (cells, buckets, runs) must carry nothing over.
    let mut grid = BroadPhase::new();
    for (n, seed) in [(3_000, 35), (50, 36), (0, 37), (2_000, 38)] {
        let boxes = clustered_boxes(n, 3, seed);
        grid.find_pairs(&boxes, &mut out);
        assert_eq!(out, brute_force_pairs(&boxes), "grid reuse after {n} boxes");
    }
}

#[test]
fn static_pairs_are_filtered_and_others_kept() {
    let boxes = clustered_boxes(3_000, 4, 41);
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let is_static: Vec<bool> = (0..boxes.len()).map(|_| rng.random_bool(0.3)).collect();
    let filtered = sweep_and_prune_filtered(&boxes, &is_static).unwrap();
    assert_eq!(
        filtered,
        brute_force_pairs_filtered(&boxes, &is_static).unwrap()
    );
    assert!(
        filtered
            .iter()
            .all(|&(i, j)| !(is_static[i as usize] && is_static[j as usize]))
    );
    let all = sweep_and_prune(&boxes);
    let static_static = all
        .iter()
        .filter(|&&(i, j)| is_static[i as usize] && is_static[j as usize])
        .count();
    // With 30% static boxes about 9% of pairs are static-static: the filter must drop exactly
    // those and nothing else.
    assert!(
        static_static > 0,
        "the test scene must contain static-static pairs"
    );
    assert_eq!(filtered.len() + static_static, all.len());
    // The grid applies the same filter.
    assert_eq!(
        broad_phase_pairs_filtered(&boxes, &is_static).unwrap(),
        filtered
    );
}

#[test]
fn filter_length_mismatch_is_an_error() {
    let boxes = sparse_boxes(10, 5.0, 51);
    let err = sweep_and_prune_filtered(&boxes, &[false; 9]).unwrap_err();
    assert_eq!(
        err,
        BroadPhaseError::FlagCountMismatch {
            boxes: 10,
            flags: 9
        }
    );
    assert!(brute_force_pairs_filtered(&boxes, &[true; 11]).is_err());
    assert_eq!(
        broad_phase_pairs_filtered(&boxes, &[false; 9]).unwrap_err(),
        err
    );
}

#[test]
fn non_finite_and_inverted_boxes_never_pair_but_do_not_disturb_the_rest() {
    let mut boxes = sparse_boxes(500, 8.0, 61);
    boxes[3].min.x = f32::NAN;
    boxes[40].max.y = f32::NAN;
    boxes[77].max.z = f32::NEG_INFINITY;
    // Inverted along x: min > max.
    boxes[100] = Aabb::new(Point3::new(5.0, 0.0, 0.0), Point3::new(4.0, 8.0, 8.0));
    let pairs = sweep_and_prune(&boxes);
    assert_eq!(pairs, brute_force_pairs(&boxes));
    assert_eq!(broad_phase_pairs(&boxes), pairs, "grid");
    for bad in [3, 40, 77, 100] {
        assert!(
            pairs.iter().all(|&(i, j)| i != bad && j != bad),
            "box {bad} paired"
        );
    }
}

#[test]
fn the_resting_pyramid_equals_brute_force_with_its_floor_on_the_side_list() {
    // The scene the grid is built for: a packed pyramid of unit cubes (each box touching up
    // to 26 neighbours through its margin) on a floor 100 times wider. The floor must go to
    // the side list, so that the cells stay one cube across, and the pairs, filtered as the
    // step filters them, must equal the reference's exactly.
    let scene = tumble_scenes::pyramid(24);
    let (aabbs, immovable) = resting_aabbs(&scene);
    let expected = brute_force_pairs_filtered(&aabbs, &immovable).unwrap();
    let mut grid = BroadPhase::new();
    let mut out = Vec::new();
    grid.find_pairs_filtered(&aabbs, &immovable, &mut out)
        .unwrap();
    assert_eq!(out, expected);
    assert_eq!(grid.oversized(), 1, "the floor alone is oversized");
    assert!(grid.cell_size() < 1.1, "cell {}", grid.cell_size());
    // About 7.6 pairs per cube: a test with few pairs would prove little.
    assert!(expected.len() > 7 * aabbs.len(), "{} pairs", expected.len());
}
