//! The grid broad phase ([`crate::BroadPhase`]) against the brute-force reference: seeded
//! random scenes of every kind the step meets (and some it should never meet), each compared
//! pair for pair, in order.

use std::ops::Range;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Aabb, Point3, Real};

use crate::{
    BroadPhase, broad_phase_pairs, broad_phase_pairs_filtered, brute_force_pairs,
    brute_force_pairs_filtered, sweep_and_prune,
};

fn aabb(min: [Real; 3], max: [Real; 3]) -> Aabb {
    Aabb::new(Point3::from(min), Point3::from(max))
}

fn centred(c: [Real; 3], h: [Real; 3]) -> Aabb {
    aabb(
        std::array::from_fn(|k| c[k] - h[k]),
        std::array::from_fn(|k| c[k] + h[k]),
    )
}

/// The grid's pairs equal the reference's exactly (same pairs, same order), through the free
/// function and through a reused `BroadPhase`; returns the number of pairs.
fn check(boxes: &[Aabb], what: &str) -> usize {
    let expected = brute_force_pairs(boxes);
    assert_eq!(broad_phase_pairs(boxes), expected, "{what}");
    let mut bp = BroadPhase::new();
    let mut out = vec![(5, 5)];
    bp.find_pairs(boxes, &mut out);
    assert_eq!(out, expected, "{what}, reused");
    expected.len()
}

/// Whether the grid of `boxes` gets a bucket per cell (else its rows are hashed).
fn dense(boxes: &[Aabb]) -> bool {
    let mut bp = BroadPhase::new();
    bp.find_pairs(boxes, &mut Vec::new());
    bp.was_dense()
}

/// `n` boxes with centres uniform in `centres` and half extents uniform in `half`, per axis
/// (each box draws its centre, then its half extents).
fn uniform_boxes(
    rng: &mut ChaCha8Rng,
    n: usize,
    centres: Range<Real>,
    half: Range<Real>,
) -> Vec<Aabb> {
    (0..n)
        .map(|_| {
            let c = std::array::from_fn(|_| rng.random_range(centres.clone()));
            centred(c, std::array::from_fn(|_| rng.random_range(half.clone())))
        })
        .collect()
}

/// Half extents log-uniform in `[lo, hi]`, per axis.
fn log_uniform(rng: &mut ChaCha8Rng, lo: Real, hi: Real) -> Real {
    (rng.random_range(lo.ln()..hi.ln())).exp()
}

#[test]
fn empty_and_one_box_have_no_pairs() {
    // The degenerate inputs: no grid boxes at all, or one with nothing to meet.
    assert!(broad_phase_pairs(&[]).is_empty());
    let one = [aabb([0.0; 3], [1.0; 3])];
    assert!(broad_phase_pairs(&one).is_empty());
    let mut bp = BroadPhase::new();
    let mut out = vec![(1, 2)];
    bp.find_pairs(&one, &mut out);
    assert!(out.is_empty(), "stale pairs must be cleared");
}

#[test]
fn uniform_random_scenes_equal_brute_force() {
    // The bench's kind of scene: similar box sizes, about one neighbour per box; the grid's
    // common path (no side list) at several densities and sizes.
    let mut total = 0;
    for (k, (n, density)) in [(2, 0.3), (40, 0.3), (500, 0.3), (3_000, 0.3), (3_000, 2.0)]
        .into_iter()
        .enumerate()
    {
        let mut rng = ChaCha8Rng::seed_from_u64(100 + k as u64);
        let extent = (n as Real / density).cbrt();
        let boxes = uniform_boxes(&mut rng, n, 0.0..extent, 0.05..0.5);
        total += check(&boxes, &format!("uniform n = {n}, density {density}"));
        assert!(dense(&boxes), "a uniform scene gets a bucket per cell");
    }
    assert!(
        total > 3_000,
        "only {total} pairs: the scenes prove too little"
    );
}

#[test]
fn sizes_from_a_millimetre_to_a_kilometre_equal_brute_force() {
    // Half extents log-uniform over 1e-3..1e3 (the engine's range): the median sets the cell,
    // a large share of boxes is oversized and goes through the side list, and side boxes
    // meet each other, grid boxes, and both.
    for seed in 0..4 {
        let mut rng = ChaCha8Rng::seed_from_u64(200 + seed);
        let n = 1_500;
        let boxes: Vec<Aabb> = (0..n)
            .map(|_| {
                let c = std::array::from_fn(|_| rng.random_range(-500.0..500.0));
                centred(c, std::array::from_fn(|_| log_uniform(&mut rng, 1e-3, 1e3)))
            })
            .collect();
        let pairs = check(&boxes, &format!("log-uniform sizes, seed {seed}"));
        assert!(pairs > 500, "seed {seed}: only {pairs} pairs");
        let mut bp = BroadPhase::new();
        bp.find_pairs(&boxes, &mut Vec::new());
        assert!(bp.oversized() > 0, "the side list must be exercised");
    }
}

#[test]
fn a_few_oversized_boxes_among_small_ones_equal_brute_force() {
    // Floors, walls and planks among unit-sized boxes: the pyramid's case. The big boxes
    // must go to the side list and the cell must stay at the small boxes' size.
    let mut rng = ChaCha8Rng::seed_from_u64(300);
    let mut boxes = uniform_boxes(&mut rng, 2_000, -15.0..15.0, 0.2..0.6);
    // A floor, a wall along z, a plank along x, inserted among the small boxes.
    boxes.insert(0, centred([0.0, -15.0, 0.0], [50.0, 0.5, 50.0]));
    boxes.insert(700, centred([3.0, 0.0, 0.0], [0.5, 20.0, 20.0]));
    boxes.push(centred([0.0, 2.0, 1.0], [30.0, 0.3, 0.3]));
    check(&boxes, "oversized among small");
    let mut bp = BroadPhase::new();
    bp.find_pairs(&boxes, &mut Vec::new());
    assert_eq!(
        bp.oversized(),
        3,
        "exactly the floor, the wall and the plank"
    );
    assert!(
        bp.cell_size() < 1.3,
        "cell {} set by the big boxes",
        bp.cell_size()
    );
}

#[test]
fn clustered_piles_equal_brute_force() {
    // Dense piles far apart: many boxes per cell, many pairs per box, and cells of distant
    // clusters sharing hash buckets.
    for (clusters, seed) in [(1, 400), (7, 401), (40, 402)] {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let centres: Vec<[Real; 3]> = (0..clusters)
            .map(|_| std::array::from_fn(|_| rng.random_range(-500.0..500.0)))
            .collect();
        let boxes: Vec<Aabb> = (0..2_500)
            .map(|i| {
                let o = centres[i % clusters];
                let c = std::array::from_fn(|k| o[k] + rng.random_range(-3.0..3.0));
                centred(c, std::array::from_fn(|_| rng.random_range(0.1..0.7)))
            })
            .collect();
        let pairs = check(&boxes, &format!("{clusters} clusters"));
        // One pile fills its grid; piles 1 km apart leave it nearly empty: hashed rows.
        assert_eq!(dense(&boxes), clusters == 1, "{clusters} clusters");
        assert!(pairs > 1_000, "{clusters} clusters: only {pairs} pairs");
    }
}

#[test]
fn huge_coordinates_equal_brute_force() {
    // Bodies near the engine's bound |pos| <= 32768, where f32 spacing is about 4 mm: cells
    // at large coordinates and boxes on both sides of the origin and of cell boundaries.
    for (half, seed) in [(1e-3, 500), (0.5, 501), (40.0, 502)] {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let boxes: Vec<Aabb> = (0..1_500)
            .map(|i| {
                // Half the boxes in a corner cluster, half spread over the whole range.
                let c: [Real; 3] = if i % 2 == 0 {
                    std::array::from_fn(|_| 32_768.0 - rng.random_range(0.0..10.0 * half))
                } else {
                    std::array::from_fn(|_| rng.random_range(-32_768.0..32_768.0))
                };
                centred(
                    c,
                    std::array::from_fn(|_| half * rng.random_range(0.5..1.0)),
                )
            })
            .collect();
        let pairs = check(&boxes, &format!("huge coordinates, half size {half}"));
        assert!(!dense(&boxes), "spread over 64 km: hashed rows");
        assert!(pairs > 100, "half size {half}: only {pairs} pairs");
    }
}

#[test]
fn exactly_touching_boxes_on_cell_boundaries_pair() {
    // A grid of cubes of side 0.5, each exactly touching its 26 neighbours: the cell size
    // comes out a hair over 0.5, so shared faces fall on and near cell boundaries, where an
    // off-by-one cell range would lose pairs.
    let side = 0.5;
    let mut boxes = Vec::new();
    for i in 0..9 {
        for j in 0..6 {
            for k in 0..7 {
                let min = [
                    i as Real * side - 2.0,
                    j as Real * side,
                    k as Real * side + 1.0,
                ];
                boxes.push(aabb(min, min.map(|v| v + side)));
            }
        }
    }
    // Interior cubes pair with all 26 neighbours: (3m - 2) per axis, see broad_phase.rs.
    let expected = ((3 * 9 - 2) * (3 * 6 - 2) * (3 * 7 - 2) - 9 * 6 * 7) / 2;
    assert_eq!(check(&boxes, "touching grid"), expected);
}

#[test]
fn point_boxes_and_identical_boxes_all_pair() {
    // No box has a positive size: the cell size falls back to 1 and everything shares one
    // cell; every pair must still come out once, in order.
    let p = aabb([1.0, 2.0, 3.0], [1.0, 2.0, 3.0]);
    assert_eq!(check(&vec![p; 60], "identical points"), 60 * 59 / 2);
    let b = aabb([-1.0, 2.0, 3.0], [1.0, 2.5, 3.5]);
    assert_eq!(check(&vec![b; 60], "identical boxes"), 60 * 59 / 2);
}

#[test]
fn nan_infinite_and_inverted_boxes_equal_brute_force() {
    // Boxes no valid step produces: NaN bounds (never pair), infinite ones and inverted ones
    // (which can still pair by the closed-interval rule, as brute force says). They must go
    // to the side list or be skipped without disturbing the grid boxes.
    let mut rng = ChaCha8Rng::seed_from_u64(600);
    let mut boxes = uniform_boxes(&mut rng, 800, 0.0..12.0, 0.1..0.6);
    boxes[3].min.x = Real::NAN;
    boxes[40].max.y = Real::NAN;
    boxes[77].max.z = Real::INFINITY;
    boxes[78].min.x = Real::NEG_INFINITY;
    boxes[79] = aabb([Real::NEG_INFINITY; 3], [Real::INFINITY; 3]);
    // Inverted along x, inside a long box that spans it: a pair by the closed-interval test.
    boxes[100] = aabb([5.0, 0.0, 0.0], [4.0, 8.0, 8.0]);
    boxes[101] = aabb([0.0, 1.0, 1.0], [10.0, 2.0, 2.0]);
    let expected = brute_force_pairs(&boxes);
    assert!(expected.contains(&(100, 101)), "the inverted box pairs");
    assert!(expected.iter().filter(|p| p.0 == 79 || p.1 == 79).count() > 700);
    check(&boxes, "non-finite and inverted");
}

#[test]
fn input_order_does_not_matter_beyond_renaming() {
    // Spatially sorted input (as scene builders emit) and shuffled input: the pairs are the
    // same boxes, renamed, and come out sorted either way.
    let mut rng = ChaCha8Rng::seed_from_u64(700);
    let mut boxes = uniform_boxes(&mut rng, 1_200, 0.0..10.0, 0.1..0.5);
    boxes.sort_by(|a, b| a.min.x.total_cmp(&b.min.x));
    check(&boxes, "sorted along x");
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    for k in (1..order.len()).rev() {
        order.swap(k, rng.random_range(0..=k));
    }
    let shuffled: Vec<Aabb> = order.iter().map(|&k| boxes[k]).collect();
    check(&shuffled, "shuffled");
}

#[test]
fn the_static_filter_and_reuse_match_the_reference() {
    // The filter of the step (static-static pairs dropped, nothing else), and one
    // `BroadPhase` reused across scenes of different sizes and kinds: no stale state.
    let mut rng = ChaCha8Rng::seed_from_u64(800);
    let mut bp = BroadPhase::new();
    let mut out = Vec::new();
    for n in [3_000usize, 10, 0, 1, 2_000] {
        let boxes: Vec<Aabb> = (0..n)
            .map(|i| {
                let c = std::array::from_fn(|_| rng.random_range(0.0..15.0));
                let h = if i % 97 == 0 { 8.0 } else { 0.4 };
                centred(c, std::array::from_fn(|_| h * rng.random_range(0.3..1.0)))
            })
            .collect();
        let flags: Vec<bool> = (0..n).map(|_| rng.random_bool(0.4)).collect();
        let expected = brute_force_pairs_filtered(&boxes, &flags).unwrap();
        bp.find_pairs_filtered(&boxes, &flags, &mut out).unwrap();
        assert_eq!(out, expected, "filtered, n = {n}");
        assert_eq!(
            broad_phase_pairs_filtered(&boxes, &flags).unwrap(),
            expected
        );
        bp.find_pairs(&boxes, &mut out);
        assert_eq!(out, brute_force_pairs(&boxes), "unfiltered, n = {n}");
        // The one-axis sweep, kept as a second reference, agrees too.
        assert_eq!(out, sweep_and_prune(&boxes), "sweep, n = {n}");
    }
    assert!(
        bp.find_pairs_filtered(&[aabb([0.0; 3], [1.0; 3])], &[], &mut out)
            .is_err()
    );
}

#[test]
fn one_broad_phase_reused_across_scenes_of_every_size_forgets_the_last() {
    // The grid keeps its buffer of found pairs at its longest between calls: a large dense
    // scene, then a smaller one, a hashed one and an empty one through the same
    // `BroadPhase` must each give exactly their own pairs (no pair left over from a longer
    // call, none lost to a stale length).
    let mut rng = ChaCha8Rng::seed_from_u64(700);
    let big = uniform_boxes(&mut rng, 3_000, 0.0..(3_000.0 / 2.0_f32).cbrt(), 0.05..0.5);
    let small = uniform_boxes(&mut rng, 200, 0.0..4.0, 0.05..0.5);
    let spread = uniform_boxes(&mut rng, 300, -5_000.0..5_000.0, 1.0..400.0);
    let mut bp = BroadPhase::new();
    let mut out = Vec::new();
    for (boxes, what) in [
        (&big, "dense, 3,000 boxes"),
        (&small, "dense, 200 boxes"),
        (&spread, "hashed"),
        (&Vec::new(), "empty"),
        (&big, "dense again"),
    ] {
        bp.find_pairs(boxes, &mut out);
        assert_eq!(out, brute_force_pairs(boxes), "{what}");
    }
    assert!(dense(&big) && dense(&small) && !dense(&spread));
    assert!(
        !brute_force_pairs(&spread).is_empty(),
        "the hashed scene must have pairs"
    );
    assert!(
        brute_force_pairs(&big).len() > 5 * brute_force_pairs(&small).len(),
        "the first scene must leave a longer buffer than the second needs"
    );
}
