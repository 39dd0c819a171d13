//! The broad phase's own specification, run by `cargo test -p tumble-broad`: a hand-checked
//! scene whose pairs are known, sweep-and-prune against the brute-force reference on seeded
//! random scenes, the sweep-axis heuristic and the static filter.
//!
//! The wider cross-checks (rotated clusters, touching grids, GPU mirrors) live in the
//! `tumble-tests` package; these are the ones small enough to run for every mutant.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Aabb, Point3, Real};

use crate::{
    BroadPhaseError, SweepAndPrune, brute_force_pairs, brute_force_pairs_filtered, sweep_and_prune,
    sweep_and_prune_filtered, sweep_axis,
};

fn aabb(min: [Real; 3], max: [Real; 3]) -> Aabb {
    Aabb::new(Point3::from(min), Point3::from(max))
}

/// Five boxes spread along x, so x is the sweep axis. Written out by hand:
/// - 0 and 1 overlap on every axis;
/// - 1 and 2 exactly touch along x (1.max.x == 2.min.x) and overlap on y and z: a pair;
/// - 2 and 3 overlap along x and z but are apart along y by 0.01: no pair;
/// - 3 and 4 overlap along x and y but are apart along z: no pair;
/// - 0 and 2 are apart along x: no pair.
fn hand_scene() -> Vec<Aabb> {
    vec![
        aabb([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
        aabb([0.5, 0.5, 0.5], [2.0, 1.5, 1.5]),
        aabb([2.0, 0.0, 0.0], [3.0, 1.0, 1.0]),
        aabb([2.5, 1.01, 0.0], [4.0, 2.0, 1.0]),
        aabb([3.5, 1.2, 1.5], [5.0, 1.8, 2.0]),
    ]
}

const HAND_PAIRS: [(u32, u32); 2] = [(0, 1), (1, 2)];

#[test]
fn the_hand_scene_gives_exactly_its_known_pairs() {
    let boxes = hand_scene();
    assert_eq!(sweep_axis(&boxes), 0, "the boxes spread along x");
    assert_eq!(sweep_and_prune(&boxes), HAND_PAIRS);
    assert_eq!(brute_force_pairs(&boxes), HAND_PAIRS);
    // The same scene with the input order reversed: pairs are renamed, still (i < j), sorted.
    let reversed: Vec<Aabb> = boxes.iter().rev().copied().collect();
    let n = boxes.len() as u32 - 1;
    let mut expected: Vec<(u32, u32)> = HAND_PAIRS
        .iter()
        .map(|&(i, j)| ((n - j), (n - i)))
        .collect();
    expected.sort_unstable();
    assert_eq!(sweep_and_prune(&reversed), expected);
    assert_eq!(brute_force_pairs(&reversed), expected);
}

#[test]
fn the_hand_scene_swept_along_y_and_z_gives_the_same_pairs() {
    // Rotating the coordinates moves the spread onto y, then z: the sweep must follow it and
    // the other two axes must still be tested.
    for shift in 1..3 {
        let boxes: Vec<Aabb> = hand_scene()
            .iter()
            .map(|b| {
                let rot = |p: Point3| {
                    Point3::new(p[(3 - shift) % 3], p[(4 - shift) % 3], p[(5 - shift) % 3])
                };
                Aabb::new(rot(b.min), rot(b.max))
            })
            .collect();
        assert_eq!(
            sweep_axis(&boxes),
            shift,
            "the spread moved to axis {shift}"
        );
        let mut sap = SweepAndPrune::new();
        let mut out = vec![(9, 9)];
        sap.find_pairs(&boxes, &mut out);
        assert_eq!(out, HAND_PAIRS, "axis {shift}");
        assert_eq!(sap.last_axis(), shift);
        assert_eq!(brute_force_pairs(&boxes), HAND_PAIRS, "axis {shift}");
    }
}

/// `n` boxes with centres uniform in a cube of side `extent`, half sizes in `[0.05, 0.6]`:
/// at `extent = n^(1/3)` about one neighbour per box, so hits and misses on every axis.
fn random_boxes(n: usize, extent: Real, seed: u64) -> Vec<Aabb> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let c: [Real; 3] = std::array::from_fn(|_| rng.random_range(0.0..extent));
            let h: [Real; 3] = std::array::from_fn(|_| rng.random_range(0.05..0.6));
            aabb(
                std::array::from_fn(|k| c[k] - h[k]),
                std::array::from_fn(|k| c[k] + h[k]),
            )
        })
        .collect()
}

/// An independent statement of the pair contract, for checking the reference itself: closed
/// intervals on all three axes, written without `Aabb::intersects`.
fn pairs_by_definition(boxes: &[Aabb]) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for i in 0..boxes.len() {
        for j in i + 1..boxes.len() {
            let (a, b) = (&boxes[i], &boxes[j]);
            if (0..3).all(|k| a.min[k] <= b.max[k] && b.min[k] <= a.max[k]) {
                out.push((i as u32, j as u32));
            }
        }
    }
    out
}

#[test]
fn sweep_equals_brute_force_on_random_scenes() {
    let mut total = 0;
    for (k, n) in [2usize, 3, 10, 50, 200, 600].into_iter().enumerate() {
        let extent = (n as Real).cbrt() * 1.2;
        let boxes = random_boxes(n, extent, 7 + k as u64);
        let expected = pairs_by_definition(&boxes);
        assert_eq!(brute_force_pairs(&boxes), expected, "brute force, n = {n}");
        assert_eq!(sweep_and_prune(&boxes), expected, "sweep, n = {n}");
        total += expected.len();
    }
    // The scenes must have pairs for the comparison to mean something (about one per box).
    assert!(total > 400, "only {total} pairs in all random scenes");
}

#[test]
fn exactly_touching_boxes_pair_on_every_axis() {
    for axis in 0..3 {
        let mut lo = [0.0; 3];
        let mut hi = [1.0; 3];
        let a = aabb(lo, hi);
        lo[axis] = 1.0;
        hi[axis] = 2.0;
        let b = aabb(lo, hi);
        // A third box far along the axis, so the spread (and the sweep) is along it.
        lo[axis] = 10.0;
        hi[axis] = 11.0;
        let c = aabb(lo, hi);
        let boxes = [a, b, c];
        assert_eq!(sweep_axis(&boxes), axis);
        assert_eq!(sweep_and_prune(&boxes), [(0, 1)], "touching along {axis}");
        assert_eq!(brute_force_pairs(&boxes), [(0, 1)], "touching along {axis}");
        // A gap of one ulp-scale step breaks the pair.
        let mut apart = b;
        apart.min[axis] = 1.0 + 1e-6;
        let boxes = [a, apart, c];
        assert!(sweep_and_prune(&boxes).is_empty(), "apart along {axis}");
        assert!(brute_force_pairs(&boxes).is_empty(), "apart along {axis}");
    }
}

#[test]
fn a_box_starting_inside_a_long_one_is_found_past_shorter_ones() {
    // Box 0 spans the whole row along x; boxes 1..=4 are small and disjoint from each other.
    // Each must pair with 0, which the sweep window of box 0 has to reach to the end.
    let mut boxes = vec![aabb([0.0, 0.0, 0.0], [10.0, 1.0, 1.0])];
    for k in 0..4 {
        let x = 1.0 + 2.0 * k as Real;
        boxes.push(aabb([x, 0.2, 0.2], [x + 0.5, 0.8, 0.8]));
    }
    let expected = [(0, 1), (0, 2), (0, 3), (0, 4)];
    assert_eq!(sweep_and_prune(&boxes), expected);
    assert_eq!(brute_force_pairs(&boxes), expected);
}

#[test]
fn sweep_axis_follows_the_largest_spread_and_breaks_ties_low() {
    let at = |c: [Real; 3]| aabb(c, c.map(|v| v + 0.1));
    assert_eq!(sweep_axis(&[]), 0);
    assert_eq!(sweep_axis(&[at([0.0, 5.0, 9.0])]), 0, "one box: axis 0");
    for axis in 0..3 {
        let mut far = [0.0; 3];
        far[axis] = 3.0;
        let mut near = [0.0; 3];
        near[(axis + 1) % 3] = 1.0;
        let boxes = [at([0.0; 3]), at(far), at(near)];
        assert_eq!(sweep_axis(&boxes), axis, "spread along {axis}");
    }
    // Equal spread on y and z, none on x: the tie goes to y.
    let boxes = [at([0.0, 0.0, 0.0]), at([0.0, 2.0, 2.0])];
    assert_eq!(sweep_axis(&boxes), 1);
    // Equal on all three: axis 0.
    let boxes = [at([0.0, 0.0, 0.0]), at([2.0, 2.0, 2.0])];
    assert_eq!(sweep_axis(&boxes), 0);
    // Variance, not extent or mean: on x two clusters 4 m apart (variance 4); on y one box
    // 6 m out among four at 0 (variance 5.76); y wins although x has more boxes spread out.
    let boxes = [
        at([0.0, 0.0, 0.0]),
        at([0.0, 0.0, 0.0]),
        at([4.0, 0.0, 0.0]),
        at([4.0, 0.0, 0.0]),
        at([2.0, 6.0, 0.0]),
    ];
    // x: centres 0,0,4,4,2 -> mean 2, variance (4+4+4+4+0)/5 = 3.2; y: 0,0,0,0,6 -> mean 1.2,
    // variance (4 * 1.44 + 23.04) / 5 = 5.76.
    assert_eq!(sweep_axis(&boxes), 1);
}

#[test]
fn sweep_axis_is_exact_far_from_the_origin() {
    // 1,000 boxes 1e5 m out, spread 0.1 m along x and 0.2 m along z: in f32 the sum of
    // squares would cancel to noise; in f64 z wins.
    let boxes: Vec<Aabb> = (0..1000)
        .map(|i| {
            let t = (i % 10) as Real / 10.0;
            let c = [1.0e5 + 0.1 * t, 1.0e5, 1.0e5 + 0.2 * t];
            aabb(c, c.map(|v| v + 0.05))
        })
        .collect();
    assert_eq!(sweep_axis(&boxes), 2);
}

#[test]
fn the_static_filter_drops_only_pairs_of_two_static_boxes() {
    let boxes = hand_scene();
    // 0 static, 1 static, 2 dynamic: (0, 1) is static-static and goes, (1, 2) stays.
    let flags = [true, true, false, false, false];
    assert_eq!(sweep_and_prune_filtered(&boxes, &flags).unwrap(), [(1, 2)]);
    assert_eq!(
        brute_force_pairs_filtered(&boxes, &flags).unwrap(),
        [(1, 2)]
    );
    // One static side is enough to keep a pair.
    let flags = [true, false, true, false, false];
    assert_eq!(
        sweep_and_prune_filtered(&boxes, &flags).unwrap(),
        HAND_PAIRS
    );
    assert_eq!(
        brute_force_pairs_filtered(&boxes, &flags).unwrap(),
        HAND_PAIRS
    );
    // Random scenes: the filtered list is the unfiltered one without static-static pairs.
    let boxes = random_boxes(300, 8.0, 99);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let flags: Vec<bool> = (0..boxes.len()).map(|_| rng.random_bool(0.5)).collect();
    let expected: Vec<(u32, u32)> = pairs_by_definition(&boxes)
        .into_iter()
        .filter(|&(i, j)| !(flags[i as usize] && flags[j as usize]))
        .collect();
    assert!(expected.len() > 50, "too few pairs: {}", expected.len());
    assert_eq!(sweep_and_prune_filtered(&boxes, &flags).unwrap(), expected);
    assert_eq!(
        brute_force_pairs_filtered(&boxes, &flags).unwrap(),
        expected
    );
    let mut sap = SweepAndPrune::new();
    let mut out = vec![(7, 7)];
    sap.find_pairs_filtered(&boxes, &flags, &mut out).unwrap();
    assert_eq!(out, expected);
}

#[test]
fn a_wrong_flag_count_is_an_error_naming_both_counts() {
    let boxes = hand_scene();
    let expected = BroadPhaseError::FlagCountMismatch { boxes: 5, flags: 4 };
    assert_eq!(
        sweep_and_prune_filtered(&boxes, &[false; 4]),
        Err(expected.clone())
    );
    assert_eq!(
        brute_force_pairs_filtered(&boxes, &[false; 4]),
        Err(expected.clone())
    );
    let mut sap = SweepAndPrune::new();
    let mut out = Vec::new();
    assert_eq!(
        sap.find_pairs_filtered(&boxes, &[false; 4], &mut out),
        Err(expected)
    );
    assert_eq!(
        sweep_and_prune_filtered(&boxes, &[false; 6]),
        Err(BroadPhaseError::FlagCountMismatch { boxes: 5, flags: 6 })
    );
}

#[test]
fn a_reused_sweep_forgets_the_last_scene() {
    let mut sap = SweepAndPrune::new();
    let mut out = Vec::new();
    let big = random_boxes(200, 6.0, 3);
    sap.find_pairs(&big, &mut out);
    assert_eq!(out, pairs_by_definition(&big));
    // A smaller scene next: no stale boxes or pairs from the first.
    let small = hand_scene();
    sap.find_pairs(&small, &mut out);
    assert_eq!(out, HAND_PAIRS);
}

#[test]
fn nan_boxes_pair_with_nothing_and_the_rest_still_pair() {
    let mut boxes = hand_scene();
    boxes.push(aabb([Real::NAN, 0.0, 0.0], [Real::NAN, 1.0, 1.0]));
    boxes.insert(0, aabb([0.5, Real::NAN, 0.5], [0.6, 0.6, 0.6]));
    // Indices shift by one for the inserted box.
    let expected = [(1, 2), (2, 3)];
    assert_eq!(sweep_and_prune(&boxes), expected);
    assert_eq!(brute_force_pairs(&boxes), expected);
}

#[test]
fn sweep_axis_uses_centres_and_their_variance_about_the_mean() {
    let at = |c: [Real; 3]| aabb(c.map(|v| v - 0.5), c.map(|v| v + 0.5));
    // x: centres -3 and 3 (symmetric about 0, variance 9); y: 0 and 2 (variance 1). Products
    // of the bounds instead of their sum would see (-3.5)(-2.5) = (2.5)(3.5) on x: no spread.
    let boxes = [at([-3.0, 0.0, 0.0]), at([3.0, 2.0, 0.0])];
    assert_eq!(sweep_axis(&boxes), 0);
    // y: centres 97, 100, 103 around a large mean (variance 6); x: -0.5, 0, 0.5 (variance
    // 1/6). Subtracting the squared mean correctly leaves y ahead.
    let boxes = [
        at([-0.5, 97.0, 0.0]),
        at([0.0, 100.0, 0.0]),
        at([0.5, 103.0, 0.0]),
    ];
    assert_eq!(sweep_axis(&boxes), 1);
    // The other way round: y has the large mean (100) but a tiny spread (variance 1/150), x
    // the spread (variance 2/3) about 0. Both terms of the variance must be averaged over
    // the boxes for the mean-zero axis to win.
    let boxes = [
        at([-1.0, 100.0, 0.0]),
        at([0.0, 100.1, 0.0]),
        at([1.0, 100.2, 0.0]),
    ];
    assert_eq!(sweep_axis(&boxes), 0);
}

#[test]
fn the_grouped_grid_drops_exactly_the_pairs_whose_groups_refuse_each_other() {
    use crate::{BroadPhase, CollisionGroups};
    let boxes = random_boxes(400, 8.0, 11);
    let is_static: Vec<bool> = (0..boxes.len()).map(|i| i % 7 == 0).collect();
    // Three groups (bits 0..3), each body colliding with a seeded subset of them: about half
    // of the pairs are refused, so a filter that ignored the groups, or that applied them to
    // one side only, would keep pairs the reference drops.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let groups: Vec<CollisionGroups> = (0..boxes.len())
        .map(|_| CollisionGroups::new(1 << rng.random_range(0..3), rng.random_range(0..8)))
        .collect();
    let expected: Vec<(u32, u32)> = brute_force_pairs_filtered(&boxes, &is_static)
        .unwrap()
        .into_iter()
        .filter(|&(i, j)| groups[i as usize].interacts_with(groups[j as usize]))
        .collect();
    let unfiltered = brute_force_pairs_filtered(&boxes, &is_static)
        .unwrap()
        .len();
    assert!(
        !expected.is_empty() && expected.len() < unfiltered,
        "the scene must have pairs kept and pairs refused"
    );
    let mut out = Vec::new();
    BroadPhase::new()
        .find_pairs_grouped(&boxes, &is_static, &groups, &mut out)
        .unwrap();
    assert_eq!(out, expected);
    // With every body in every group, the grouped query is the static filter's.
    let all = vec![CollisionGroups::ALL; boxes.len()];
    BroadPhase::new()
        .find_pairs_grouped(&boxes, &is_static, &all, &mut out)
        .unwrap();
    assert_eq!(out.len(), unfiltered);
    let e = BroadPhase::new()
        .find_pairs_grouped(&boxes, &is_static, &all[1..], &mut out)
        .unwrap_err();
    assert_eq!(
        e,
        BroadPhaseError::GroupCountMismatch {
            boxes: 400,
            groups: 399
        }
    );
}
