//! The CPU broad phase, old against new against parry3d, in one run:
//!
//! - `broad_pyramid50`: the resting packed pyramid of 50 layers (42,926 boxes with the floor),
//!   each box's AABB as the step computes it at rest (grown by the default margin), the
//!   floor flagged immovable as the step does;
//! - `broad_random`: 1k, 10k and 100k random boxes (half sizes 0.05..0.5 m, 0.3 boxes per m^3),
//!   brute force at 1k for scale.
//!
//! Rows: `grid` is [`BroadPhase`] (the grid search, buffers reused); `kept_at_rest` and
//! `kept_all_moved` are [`KeptPairs`], the step's broad phase (the grid search on enlarged
//! boxes, its pair list kept while every box stays inside its enlarged box), on the same boxes
//! every call and on boxes that all left their enlarged boxes every call; `kept_1_moved` and
//! `kept_16_moved` on boxes of which 1 or 16 left their enlarged boxes every call (the kept
//! list repaired, not searched); `sweep` the
//! one-axis [`SweepAndPrune`] it replaced (buffers reused); both return the sorted pair list.
//! `parry_bvh_build` builds a parry3d `Bvh` (binned SAH) over the boxes and traverses it
//! against itself; `parry_bvh_refit` keeps a tree built once, refits it to the boxes and
//! traverses it, as rapier3d's `BroadPhaseBvh` does each step (without its change detection,
//! which would skip unchanged pairs, so that every pair is found as ours are). parry3d's rows
//! only count the pairs: they come out unordered, in tree order.

use std::hint::black_box;

use criterion::{BenchmarkGroup, BenchmarkId, Criterion, Throughput, criterion_group};
use criterion::{criterion_main, measurement::WallTime};
use parry3d::bounding_volume::Aabb as PAabb;
use parry3d::math::Vector as PVec;
use parry3d::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};
use tumble_broad::{BroadPhase, KeptPairs, REPAIR_MAX, SweepAndPrune, brute_force_pairs};
use tumble_geometry::Aabb;
use tumble_scenes::pyramid;
use tumble_tests::scene_support::{resting_aabbs, sparse_boxes};

/// Boxes per cubic meter: about what a settled pile of 1 m boxes with gaps looks like, giving
/// each box a handful of overlapping neighbours (about 1.5 pairs per box).
const DENSITY: f32 = 0.3;

/// `n` boxes with half sizes in [0.05, 0.5] m, centres uniform in a cube holding `DENSITY`.
fn random_boxes(n: usize, seed: u64) -> Vec<Aabb> {
    sparse_boxes(n, (n as f32 / DENSITY).cbrt(), seed)
}

/// The resting pyramid of `h` layers: each body's step AABB at rest and its immovable flag.
fn pyramid_boxes(h: usize) -> (Vec<Aabb>, Vec<bool>) {
    resting_aabbs(&pyramid(h))
}

fn to_parry(aabbs: &[Aabb]) -> Vec<PAabb> {
    let v = |p: &tumble_geometry::Point3| PVec::new(p.x, p.y, p.z);
    aabbs
        .iter()
        .map(|b| PAabb::new(v(&b.min), v(&b.max)))
        .collect()
}

/// The four rows on one scene; `flags` is the immovable filter the step applies (ours only:
/// it removes one pair in a thousand on the pyramid, the floor's with nothing).
fn rows(group: &mut BenchmarkGroup<'_, WallTime>, n: usize, boxes: &[Aabb], flags: &[bool]) {
    group.throughput(Throughput::Elements(boxes.len() as u64));
    let mut pairs = Vec::new();
    let mut grid = BroadPhase::new();
    row(group, "grid", n, boxes, |boxes| {
        grid.find_pairs_filtered(boxes, flags, &mut pairs).unwrap();
        pairs.len()
    });
    // The step's broad phase: the pair list kept while every box stays inside its enlarged
    // box (the same boxes every call: the list is reused and filtered), and the worst case,
    // every box moved out of its enlarged box on every call (the whole set shifted 1 m along
    // x and back, alternately: the grid searched every call, on the enlarged boxes).
    let mut kept = KeptPairs::new();
    row(group, "kept_at_rest", n, boxes, |boxes| {
        kept.find_pairs(boxes, flags, None, &mut pairs).unwrap();
        pairs.len()
    });
    let shifted: Vec<Aabb> = boxes
        .iter()
        .map(|b| {
            let d = tumble_geometry::Vec3::new(1.0, 0.0, 0.0);
            Aabb::new(b.min + d, b.max + d)
        })
        .collect();
    let mut kept = KeptPairs::new();
    let mut flip = false;
    row(group, "kept_all_moved", n, boxes, |boxes| {
        flip = !flip;
        let input = if flip { &shifted[..] } else { boxes };
        kept.find_pairs(input, flags, None, &mut pairs).unwrap();
        pairs.len()
    });
    // A few boxes moving among many at rest (a ball rolling over a resting pile): on every
    // call 1 or 16 boxes, spread over the index range, leave their enlarged boxes (1 m along
    // x and back, alternately), so the kept list is repaired (their pairs found again alone)
    // instead of searched.
    for movers in [1, REPAIR_MAX] {
        let stride = (boxes.len() / movers).max(1);
        let shifted: Vec<Aabb> = boxes
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let moves = i % stride == stride / 2 && i / stride < movers;
                let d = tumble_geometry::Vec3::new(if moves { 1.0 } else { 0.0 }, 0.0, 0.0);
                Aabb::new(b.min + d, b.max + d)
            })
            .collect();
        let mut kept = KeptPairs::new();
        let mut flip = false;
        let name = format!("kept_{movers}_moved");
        row(group, &name, n, boxes, |boxes| {
            flip = !flip;
            let input = if flip { &shifted[..] } else { boxes };
            kept.find_pairs(input, flags, None, &mut pairs).unwrap();
            pairs.len()
        });
    }
    let mut sap = SweepAndPrune::new();
    row(group, "sweep", n, boxes, |boxes| {
        sap.find_pairs_filtered(boxes, flags, &mut pairs).unwrap();
        pairs.len()
    });
    let leaves = to_parry(boxes);
    let mut workspace = BvhWorkspace::default();
    row(group, "parry_bvh_build", n, &leaves[..], |leaves| {
        let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, leaves);
        self_pairs(&bvh, &mut workspace)
    });
    let mut bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &leaves);
    row(group, "parry_bvh_refit", n, &leaves[..], |leaves| {
        for (i, leaf) in leaves.iter().enumerate() {
            bvh.insert_or_update_partially(*leaf, i as u32, 0.0);
        }
        bvh.refit(&mut workspace);
        self_pairs(&bvh, &mut workspace)
    });
}

/// One row: `count` runs on the (black-boxed) input each iteration and returns how many pairs
/// it found; what it keeps between iterations (pair lists, trees, workspaces) it captures.
fn row<I: ?Sized>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    n: usize,
    input: &I,
    mut count: impl FnMut(&I) -> usize,
) {
    group.bench_with_input(BenchmarkId::new(name, n), input, |b, input| {
        b.iter(|| black_box(count(black_box(input))))
    });
}

/// The number of overlapping leaf pairs of a parry3d tree, traversed against itself.
fn self_pairs(bvh: &Bvh, workspace: &mut BvhWorkspace) -> usize {
    let mut count = 0usize;
    bvh.traverse_bvtt_single_tree::<false>(workspace, &mut |_, _| count += 1);
    count
}

fn broad_pyramid50(c: &mut Criterion) {
    let (boxes, flags) = pyramid_boxes(50);
    let mut group = c.benchmark_group("broad_pyramid50");
    rows(&mut group, boxes.len(), &boxes, &flags);
    group.finish();
}

fn broad_random(c: &mut Criterion) {
    let mut group = c.benchmark_group("broad_random");
    for n in [1_000, 10_000, 100_000] {
        let boxes = random_boxes(n, n as u64);
        rows(&mut group, n, &boxes, &vec![false; n]);
        if n == 1_000 {
            row(&mut group, "brute_force", n, &boxes[..], |boxes| {
                brute_force_pairs(boxes).len()
            });
        }
    }
    group.finish();
}

criterion_group!(benches, broad_pyramid50, broad_random);
criterion_main!(benches);
