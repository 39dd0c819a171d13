//! The kept list against brute force: reused, repaired and searched, on one thread and on the
//! pool.

use super::*;
use crate::brute_force_pairs_filtered;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::Point3;

fn random_box(rng: &mut ChaCha8Rng, extent: Real) -> Aabb {
    let c = Point3::new(
        rng.random_range(0.0..extent),
        rng.random_range(0.0..extent),
        rng.random_range(0.0..extent),
    );
    let h = rng.random_range(0.05..0.5);
    Aabb::new(
        c - tumble_geometry::Vec3::repeat(h),
        c + tumble_geometry::Vec3::repeat(h),
    )
}

/// The exact pairs with groups, by brute force.
fn exact(
    aabbs: &[Aabb],
    is_static: &[bool],
    groups: Option<&[CollisionGroups]>,
) -> Vec<(u32, u32)> {
    brute_force_pairs_filtered(aabbs, is_static)
        .unwrap()
        .into_iter()
        .filter(|&(i, j)| groups.is_none_or(|g| g[i as usize].interacts_with(g[j as usize])))
        .collect()
}

/// A random walk of boxes, most steps moving every box by a little (kept list reused),
/// some by a lot (searched again), with flags, groups, counts and NaN boxes changing on
/// some steps: every call's pairs equal brute force's, and both branches are taken. A
/// kept list that were not filtered by the exact boxes, or that were reused after a box
/// left its fat box or after the flags changed, fails here.
#[test]
fn kept_pairs_equal_brute_force_through_a_random_walk() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut kept = KeptPairs::new();
    let mut aabbs: Vec<Aabb> = (0..300).map(|_| random_box(&mut rng, 8.0)).collect();
    let mut is_static: Vec<bool> = (0..aabbs.len()).map(|_| rng.random_bool(0.1)).collect();
    let mut groups: Vec<CollisionGroups> = vec![CollisionGroups::ALL; aabbs.len()];
    let mut out = Vec::new();
    let mut last_reuse = 0;
    for step in 0..200 {
        // Small moves: a millimetre, well inside a fat margin of at least 1 cm; jumps of up
        // to half a metre on some steps, and on every step of 100..120 (a scene in
        // motion: searches on the exact boxes, a retry on fat boxes every RETRY_EVERY).
        let jump = step % 17 == 5 || (100..120).contains(&step);
        for a in aabbs.iter_mut() {
            let d = if jump { 0.5 } else { 0.001 };
            let v = tumble_geometry::Vec3::new(
                rng.random_range(-d..d),
                rng.random_range(-d..d),
                rng.random_range(-d..d),
            );
            a.min += v;
            a.max += v;
        }
        if step % 23 == 7 {
            let k = rng.random_range(0..aabbs.len());
            is_static[k] = !is_static[k];
        }
        if step % 29 == 11 {
            aabbs.push(random_box(&mut rng, 8.0));
            is_static.push(false);
            groups.push(CollisionGroups::ALL);
        }
        if step % 31 == 13 {
            let k = rng.random_range(0..aabbs.len());
            groups[k] = CollisionGroups::new(0b10, 0b10);
        }
        let nan_step = step % 37 == 19;
        let saved = aabbs[0];
        if nan_step {
            aabbs[0].min.x = Real::NAN;
        }
        let grouped = (step / 50) % 2 == 1;
        let g = grouped.then_some(groups.as_slice());
        kept.find_pairs(&aabbs, &is_static, g, &mut out).unwrap();
        assert_eq!(out, exact(&aabbs, &is_static, g), "step {step}");
        if nan_step {
            assert!(
                !kept.reused_last() || kept.repaired_last(),
                "a NaN box is never inside its fat box"
            );
            aabbs[0] = saved;
        }
        if (101..120).contains(&step) {
            assert!(!kept.reused_last(), "step {step}: every box jumped");
        }
        if kept.reused_last() {
            last_reuse = step;
        }
        // Within RETRY_EVERY calls of a search on the exact boxes comes one on fat boxes,
        // and the list is reused after it; the flag change of step 122 and the jump of
        // step 124 each drop a list, so allow two such waits.
        if step == 120 + 2 * RETRY_EVERY as usize + 1 {
            assert!(last_reuse > 120, "at rest again, reused by step {step}");
        }
    }
    let (searches, reuses) = kept.counts();
    assert!(
        searches >= 20 && reuses >= 50,
        "searches {searches}, reuses {reuses}"
    );
}

/// At rest the list is reused; a box moved out of its fat box has its pairs found again
/// alone (the list repaired), and more than [`REPAIR_MAX`] such boxes make it search again.
#[test]
fn a_box_leaving_its_fat_box_is_repaired_and_many_make_it_search_again() {
    let n = 40;
    let boxes: Vec<Aabb> = (0..n)
        .map(|i| {
            let x = i as Real * 1.0;
            Aabb::new(Point3::new(x, 0.0, 0.0), Point3::new(x + 1.0, 1.0, 1.0))
        })
        .collect();
    let flags = vec![false; boxes.len()];
    let mut kept = KeptPairs::new();
    let mut out = Vec::new();
    kept.find_pairs(&boxes, &flags, None, &mut out).unwrap();
    assert!(!kept.reused_last());
    kept.find_pairs(&boxes, &flags, None, &mut out).unwrap();
    assert!(kept.reused_last() && !kept.repaired_last());
    assert_eq!(out.len(), n - 1, "touching neighbours pair: {out:?}");
    // 9 cm is inside the 10 cm fat margin of a 1 m box; 11 cm is not.
    let mut moved = boxes.clone();
    moved[4].min.y += 0.09;
    moved[4].max.y += 0.09;
    kept.find_pairs(&moved, &flags, None, &mut out).unwrap();
    assert!(kept.reused_last() && !kept.repaired_last());
    moved[4].min.y += 0.02;
    moved[4].max.y += 0.02;
    kept.find_pairs(&moved, &flags, None, &mut out).unwrap();
    assert!(kept.reused_last() && kept.repaired_last());
    assert_eq!(out, brute_force_pairs_filtered(&moved, &flags).unwrap());
    // Box 4 lifted clear of its neighbours (1.2 m up), box 30 put on top of box 10: their
    // old pairs go, the new one comes.
    for (k, dx, dy) in [(4, 0.0, 1.09), (30, -20.0, 1.0)] {
        moved[k].min.x += dx;
        moved[k].max.x += dx;
        moved[k].min.y += dy;
        moved[k].max.y += dy;
    }
    kept.find_pairs(&moved, &flags, None, &mut out).unwrap();
    assert!(kept.repaired_last());
    let expected = brute_force_pairs_filtered(&moved, &flags).unwrap();
    assert!(expected.contains(&(10, 30)) && !expected.contains(&(3, 4)));
    assert_eq!(out, expected);
    // REPAIR_MAX boxes out of their fat boxes: still repaired; one more: the search runs
    // again.
    for b in moved.iter_mut().skip(20).take(REPAIR_MAX) {
        b.min.z += 0.5;
        b.max.z += 0.5;
    }
    kept.find_pairs(&moved, &flags, None, &mut out).unwrap();
    assert!(kept.repaired_last());
    assert_eq!(out, brute_force_pairs_filtered(&moved, &flags).unwrap());
    for b in moved.iter_mut().skip(20).take(REPAIR_MAX + 1) {
        b.min.z += 0.5;
        b.max.z += 0.5;
    }
    kept.find_pairs(&moved, &flags, None, &mut out).unwrap();
    assert!(!kept.reused_last() && !kept.repaired_last());
    assert_eq!(out, brute_force_pairs_filtered(&moved, &flags).unwrap());
    assert_eq!(kept.repairs(), 3);
}

/// A kept list past [`PARALLEL_MIN`] pairs, reused on pools of one and four threads: the
/// filter and the containment check then run on the pool, and the pairs must still be
/// brute force's, in its order, with some kept pairs filtered out (so the filter's order
/// is tested, not only its count). A filter that lost rayon's order, or kept a pair whose
/// exact boxes part, fails here.
#[test]
fn a_large_kept_list_is_filtered_on_the_pool_in_order() {
    // 28 x 28 x 28 cubes of 1 m, 5 cm apart: each touches none of its neighbours, but every
    // fat box (grown 10 cm) overlaps its 26 neighbours' fat boxes, so the kept list holds
    // 264,708 pairs and the exact filter keeps those moved into contact below.
    let n = 28;
    let mut boxes = Vec::new();
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let p = Point3::new(i as Real * 1.05, j as Real * 1.05, k as Real * 1.05);
                boxes.push(Aabb::new(p, p + tumble_geometry::Vec3::repeat(1.0)));
            }
        }
    }
    let flags = vec![false; boxes.len()];
    // Every seventh box grown by 6 cm along x (inside its fat box): it touches its +x
    // neighbour.
    let mut moved = boxes.clone();
    for b in moved.iter_mut().step_by(7) {
        b.max.x += 0.06;
    }
    let expected = brute_force_pairs_filtered(&moved, &flags).unwrap();
    assert!(!expected.is_empty());
    for threads in [1, 4] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut kept = KeptPairs::new();
        let mut out = Vec::new();
        pool.install(|| kept.find_pairs(&boxes, &flags, None, &mut out))
            .unwrap();
        assert!(out.is_empty(), "the cubes stand apart: {} pairs", out.len());
        assert!(
            kept.pairs.len() > PARALLEL_MIN,
            "{} kept pairs",
            kept.pairs.len()
        );
        pool.install(|| kept.find_pairs(&moved, &flags, None, &mut out))
            .unwrap();
        assert!(kept.reused_last(), "{threads} threads");
        assert_eq!(out, expected, "{threads} threads");
        // Five boxes, in different chunks of the containment check, moved 2.25 m up (out
        // of their fat boxes, into the boxes two and three rows up, which were not in
        // their kept pairs): the check, on the pool too, must find them all, and the
        // repair their new pairs.
        let mut out_of_fat = moved.clone();
        let last = out_of_fat.len() - 1;
        for k in [0, 5_000, 10_000, 15_000, last] {
            out_of_fat[k].min.y += 2.25;
            out_of_fat[k].max.y += 2.25;
        }
        let before = out.clone();
        pool.install(|| kept.find_pairs(&out_of_fat, &flags, None, &mut out))
            .unwrap();
        assert!(kept.repaired_last(), "{threads} threads");
        let expected = brute_force_pairs_filtered(&out_of_fat, &flags).unwrap();
        assert_ne!(expected, before, "the moved boxes touch new neighbours");
        assert_eq!(out, expected, "{threads} threads");
        // REPAIR_MAX boxes, one per 1,300 (in every chunk of the check), moved 2.25 m
        // down: repaired; from the same kept list, one more: the search runs.
        let moved_down = |count: usize| {
            let mut boxes = out_of_fat.clone();
            for b in boxes.iter_mut().step_by(1_300).take(count) {
                b.min.y -= 2.25;
                b.max.y -= 2.25;
            }
            boxes
        };
        let mut one_more = kept.clone();
        let limit = moved_down(REPAIR_MAX);
        pool.install(|| kept.find_pairs(&limit, &flags, None, &mut out))
            .unwrap();
        assert!(kept.repaired_last(), "{threads} threads");
        assert_eq!(out, brute_force_pairs_filtered(&limit, &flags).unwrap());
        let past = moved_down(REPAIR_MAX + 1);
        pool.install(|| one_more.find_pairs(&past, &flags, None, &mut out))
            .unwrap();
        assert!(!one_more.reused_last(), "{threads} threads");
        assert_eq!(out, brute_force_pairs_filtered(&past, &flags).unwrap());
        // And every box moved: more than REPAIR_MAX, so the search runs.
        let shifted: Vec<Aabb> = out_of_fat
            .iter()
            .map(|b| {
                let d = tumble_geometry::Vec3::new(0.0, 0.2, 0.0);
                Aabb::new(b.min + d, b.max + d)
            })
            .collect();
        pool.install(|| kept.find_pairs(&shifted, &flags, None, &mut out))
            .unwrap();
        assert!(!kept.reused_last(), "{threads} threads");
        assert_eq!(
            out,
            brute_force_pairs_filtered(&shifted, &flags).unwrap(),
            "{threads} threads"
        );
    }
}
