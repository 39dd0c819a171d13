//! Islands and the sleep test: bodies connected through dynamic bodies share an island, fixed
//! and kinematic bodies connect nothing, labels are the smallest member; a body rests only
//! strictly below both of Box2D's tolerances.

use crate::{ANGULAR_SLEEP_TOLERANCE, Islands, LINEAR_SLEEP_TOLERANCE, TIME_TO_SLEEP, is_resting};

#[test]
fn bodies_connected_through_dynamic_bodies_share_an_island_labelled_by_the_smallest() {
    // Two chains: 5-3-1 (given out of order) and 2-4; 0 is a floor under everything and 6 is
    // kinematic, touching 4 and 5; 7 is alone.
    let dynamic = [false, true, true, true, true, true, false, true];
    let links = [
        (3, 5),
        (0, 1),
        (1, 3),
        (0, 2),
        (4, 2),
        (6, 4),
        (5, 6),
        (0, 7),
    ];
    let islands = Islands::build(&dynamic, links);
    assert_eq!(islands.label, vec![0, 1, 2, 1, 2, 1, 6, 7]);
    assert!(islands.same(5, 1) && islands.same(3, 5) && islands.same(2, 4));
    assert!(!islands.same(1, 2), "the floor joins nothing");
    assert!(!islands.same(4, 5), "a kinematic body joins nothing");
    assert!(!islands.same(0, 6) && !islands.same(7, 1));
    // A long chain given from the far end, so the union-find trees get deep.
    let n = 64;
    let links: Vec<(u32, u32)> = (1..n).rev().map(|i| (i, i - 1)).collect();
    let islands = Islands::build(&vec![true; n as usize], links.iter().copied());
    assert!(islands.label.iter().all(|&l| l == 0), "{:?}", islands.label);
    // Joining two chains of different sizes in either order gives the same labels.
    for order in [
        [(0u32, 1u32), (1, 2), (3, 4), (2, 3)],
        [(3, 4), (2, 3), (1, 2), (0, 1)],
    ] {
        let islands = Islands::build(&[true; 5], order);
        assert_eq!(islands.label, vec![0; 5]);
    }
    // A body linked to itself is still its own island.
    assert_eq!(Islands::build(&[true, true], [(1, 1)]).label, vec![0, 1]);
    assert_eq!(Islands::build(&[], []).label, Vec::<u32>::new());
}

#[test]
fn a_body_rests_strictly_below_both_tolerances() {
    // Box2D's values: 5 cm/s, 2 degrees per second, half a second.
    assert_eq!(LINEAR_SLEEP_TOLERANCE, 0.05);
    assert!((ANGULAR_SLEEP_TOLERANCE - 2.0f32.to_radians()).abs() < 1e-7);
    assert_eq!(TIME_TO_SLEEP, 0.5);
    let (lin, ang) = (LINEAR_SLEEP_TOLERANCE, ANGULAR_SLEEP_TOLERANCE);
    assert!(is_resting(0.0, 0.0));
    assert!(is_resting(0.99 * lin, 0.99 * ang));
    assert!(!is_resting(lin, 0.0), "at the tolerance is not below it");
    assert!(!is_resting(0.0, ang));
    assert!(!is_resting(1.01 * lin, 0.0));
    assert!(!is_resting(0.0, 1.01 * ang));
    assert!(!is_resting(2.0 * lin, 2.0 * ang));
}
