//! `tumble_broad`'s sweep-and-prune against `brute_force_pairs`, on arbitrary AABB sets.
//!
//! The contract (crates/tumble-broad/src/lib.rs) holds for any boxes, so nothing is filtered:
//! NaN, infinite, inverted (min > max), touching and duplicate boxes all come through. Checked:
//! no panic; `sweep_and_prune` equals `brute_force_pairs` exactly; a reused `SweepAndPrune`
//! gives the same pairs on a second, different query and again on the first (its scratch
//! buffers carry nothing over); the filtered forms agree with each other and drop exactly the
//! pairs of two static boxes; a flag slice of the wrong length is an `Err`, not a panic.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use tumble_broad::{
    BroadPhaseError, SweepAndPrune, brute_force_pairs, brute_force_pairs_filtered, sweep_and_prune,
    sweep_and_prune_filtered,
};
use tumble_fuzz::{Num, vec3};
use tumble_geometry::{Aabb, Point3};

#[derive(Arbitrary, Debug)]
struct InputBox {
    /// Corner, then either a size added to it (mostly a proper box) or a second corner.
    min: [Num; 3],
    other: [Num; 3],
    other_is_size: bool,
    is_static: bool,
}

#[derive(Arbitrary, Debug)]
struct Input {
    boxes: Vec<InputBox>,
    /// How many boxes the second query keeps (a different set for the reused sweep).
    second_len: u8,
    /// Flags one short or one long instead of one per box.
    bad_flags: Option<bool>,
}

fn aabb(b: &InputBox) -> Aabb {
    let min = vec3(b.min);
    let other = vec3(b.other);
    let max = if b.other_is_size {
        [0, 1, 2].map(|k| min[k] + other[k])
    } else {
        other
    };
    Aabb::new(Point3::from(min), Point3::from(max))
}

fn check_sorted_unique(pairs: &[(u32, u32)], n: usize) {
    for w in pairs.windows(2) {
        assert!(w[0] < w[1], "not strictly ascending: {w:?}");
    }
    for &(i, j) in pairs {
        assert!(
            i < j && (j as usize) < n,
            "bad pair ({i}, {j}) of {n} boxes"
        );
    }
}

fuzz_target!(|input: Input| {
    let aabbs: Vec<Aabb> = input.boxes.iter().map(aabb).collect();
    let flags: Vec<bool> = input.boxes.iter().map(|b| b.is_static).collect();
    let n = aabbs.len();

    let reference = brute_force_pairs(&aabbs);
    let swept = sweep_and_prune(&aabbs);
    assert_eq!(
        swept, reference,
        "sweep and prune differs from brute force on {aabbs:?}"
    );
    check_sorted_unique(&swept, n);

    // A reused broad phase: a second, smaller query, then the first again.
    let mut sap = SweepAndPrune::new();
    let mut out = vec![(7, 7)];
    sap.find_pairs(&aabbs, &mut out);
    assert_eq!(out, reference, "first query of a fresh SweepAndPrune");
    let second = &aabbs[..usize::from(input.second_len).min(n)];
    sap.find_pairs(second, &mut out);
    assert_eq!(
        out,
        brute_force_pairs(second),
        "second query of a reused SweepAndPrune"
    );
    sap.find_pairs(&aabbs, &mut out);
    assert_eq!(out, reference, "first query again after a different one");

    // Filtered: exactly the pairs not both static, by both paths.
    let wanted: Vec<(u32, u32)> = reference
        .iter()
        .copied()
        .filter(|&(i, j)| !(flags[i as usize] && flags[j as usize]))
        .collect();
    assert_eq!(sweep_and_prune_filtered(&aabbs, &flags), Ok(wanted.clone()));
    assert_eq!(
        brute_force_pairs_filtered(&aabbs, &flags),
        Ok(wanted.clone())
    );
    sap.find_pairs_filtered(&aabbs, &flags, &mut out)
        .expect("one flag per box");
    assert_eq!(out, wanted);

    if let Some(longer) = input.bad_flags {
        let mut bad = flags.clone();
        if longer {
            bad.push(true);
        } else if bad.pop().is_none() {
            return;
        }
        let expected = Err(BroadPhaseError::FlagCountMismatch {
            boxes: n,
            flags: bad.len(),
        });
        assert_eq!(sweep_and_prune_filtered(&aabbs, &bad), expected);
        assert_eq!(brute_force_pairs_filtered(&aabbs, &bad), expected);
        let mut out = vec![(1, 2)];
        assert_eq!(
            sap.find_pairs_filtered(&aabbs, &bad, &mut out),
            expected.map(|_| ())
        );
        // Refused before touching the output.
        assert_eq!(out, vec![(1, 2)]);
    }
});
