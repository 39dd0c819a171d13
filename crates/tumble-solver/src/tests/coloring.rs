//! Graph coloring: the greedy lowest-free-color rule on small graphs whose coloring is known
//! by hand, the grouping into `order` and `offsets`, the visiting order, and every error of
//! `validate_coloring`.

use crate::{
    Coloring, ColoringError, GRAPH_COLOR_COUNT, OVERFLOW_COLOR, color_constraints,
    color_constraints_in_order, validate_coloring,
};

/// Contacts of a column of `n` dynamic boxes on a fixed floor (body 0): contact k joins body
/// k and k + 1, bottom first.
fn column(n: u32) -> (Vec<(u32, u32)>, Vec<bool>) {
    let pairs = (0..n).map(|k| (k, k + 1)).collect();
    let mut dynamic = vec![true; n as usize + 1];
    dynamic[0] = false;
    (pairs, dynamic)
}

/// Checks the contract of a coloring: body-disjoint colors for dynamic bodies, every
/// constraint exactly once in `order`, grouped by ascending color, ascending within a color.
fn check(pairs: &[(u32, u32)], dynamic: &[bool], coloring: &Coloring) {
    validate_coloring(pairs, dynamic, &coloring.colors).unwrap();
    assert_eq!(coloring.offsets.len(), GRAPH_COLOR_COUNT + 2);
    assert_eq!(coloring.offsets[0], 0);
    assert_eq!(*coloring.offsets.last().unwrap() as usize, pairs.len());
    let mut seen = vec![0; pairs.len()];
    for c in 0..=OVERFLOW_COLOR {
        let members = coloring.color(c);
        assert!(
            members.windows(2).all(|w| w[0] < w[1]),
            "color {c} is ascending"
        );
        for &i in members {
            assert_eq!(coloring.colors[i as usize], c);
            seen[i as usize] += 1;
        }
    }
    assert!(
        seen.iter().all(|&n| n == 1),
        "each constraint colored once: {seen:?}"
    );
}

#[test]
fn a_column_alternates_two_colors_from_the_first_visited_contact() {
    let (pairs, dynamic) = column(7);
    let bottom_up = color_constraints(&pairs, &dynamic);
    check(&pairs, &dynamic, &bottom_up);
    // Neighbouring contacts share a box; every other one shares nothing: two colors.
    assert_eq!(bottom_up.colors, vec![0, 1, 0, 1, 0, 1, 0]);
    assert_eq!(bottom_up.used_colors(), 2);
    assert_eq!(bottom_up.overflow_count(), 0);
    assert_eq!(bottom_up.order, vec![0, 2, 4, 6, 1, 3, 5]);
    // Visited top-down (upper contacts first along gravity), the top contact gets color 0,
    // which the solver visits first in each pass.
    let top_down = color_constraints_in_order(&pairs, &dynamic, (0..7).rev());
    check(&pairs, &dynamic, &top_down);
    assert_eq!(top_down.colors, vec![0, 1, 0, 1, 0, 1, 0]);
    let (pairs6, dynamic6) = column(6);
    let top_down = color_constraints_in_order(&pairs6, &dynamic6, (0..6).rev());
    assert_eq!(top_down.colors, vec![1, 0, 1, 0, 1, 0]);
    assert_eq!(top_down.color(0), &[1, 3, 5]);
}

#[test]
fn each_constraint_takes_the_lowest_color_free_for_both_its_dynamic_bodies() {
    // A triangle of dynamic bodies needs three colors; a fourth edge to a fixed body (3)
    // reuses color 0, since fixed bodies do not count.
    let pairs = [(0, 1), (1, 2), (0, 2), (2, 3), (3, 1)];
    let dynamic = [true, true, true, false];
    let coloring = color_constraints(&pairs, &dynamic);
    check(&pairs, &dynamic, &coloring);
    // (2, 3): body 2 holds colors 1 and 2, so 0. (3, 1): body 1 holds 0 and 1, so 2.
    assert_eq!(coloring.colors, vec![0, 1, 2, 0, 2]);
    assert_eq!(coloring.used_colors(), 3);
    // Two constraints between fixed or kinematic bodies only share color 0.
    let pairs = [(0, 1), (1, 0)];
    let coloring = color_constraints(&pairs, &[false, false]);
    assert_eq!(coloring.colors, vec![0, 0]);
}

#[test]
fn a_body_of_exactly_the_color_count_fits_and_one_more_overflows() {
    let n = GRAPH_COLOR_COUNT as u32;
    let pairs: Vec<(u32, u32)> = (1..=n + 1).map(|i| (0, i)).collect();
    let dynamic = vec![true; n as usize + 2];
    let coloring = color_constraints(&pairs, &dynamic);
    check(&pairs, &dynamic, &coloring);
    let expected: Vec<u32> = (0..n).chain([OVERFLOW_COLOR]).collect();
    assert_eq!(coloring.colors, expected);
    assert_eq!(coloring.used_colors(), GRAPH_COLOR_COUNT);
    assert_eq!(coloring.overflow_count(), 1);
    assert_eq!(coloring.color(OVERFLOW_COLOR), &[n]);
}

#[test]
fn grouping_is_a_stable_counting_sort_by_color() {
    let colors = vec![2, 0, OVERFLOW_COLOR, 0, 1, 2, OVERFLOW_COLOR];
    let coloring = Coloring::from_colors(colors.clone());
    assert_eq!(coloring.colors, colors);
    assert_eq!(coloring.order, vec![1, 3, 4, 0, 5, 2, 6]);
    let mut offsets = vec![0, 2, 3];
    offsets.extend(std::iter::repeat_n(5, GRAPH_COLOR_COUNT - 2));
    offsets.push(7);
    assert_eq!(coloring.offsets, offsets);
    assert_eq!(coloring.color(0), &[1, 3]);
    assert_eq!(coloring.color(1), &[4]);
    assert_eq!(coloring.color(2), &[0, 5]);
    assert_eq!(coloring.color(3), &[] as &[u32]);
    assert_eq!(coloring.color(OVERFLOW_COLOR), &[2, 6]);
    assert_eq!(coloring.used_colors(), 3);
    assert_eq!(coloring.overflow_count(), 2);
    let empty = Coloring::default();
    assert!(empty.order.is_empty() && empty.colors.is_empty());
    assert_eq!(empty.used_colors(), 0);
    assert_eq!(empty.overflow_count(), 0);
}

#[test]
fn validation_reports_each_kind_of_bad_coloring() {
    let pairs = [(0, 1), (1, 2), (2, 3)];
    let dynamic = [true, true, true, false];
    assert_eq!(
        validate_coloring(&pairs, &dynamic, &[0, 1]),
        Err(ColoringError::LengthMismatch {
            colors: 2,
            constraints: 3
        })
    );
    assert_eq!(
        validate_coloring(&pairs, &dynamic, &[0, 1, GRAPH_COLOR_COUNT as u32]),
        Ok(()),
        "the overflow color is allowed"
    );
    assert_eq!(
        validate_coloring(&pairs, &dynamic, &[0, 1, GRAPH_COLOR_COUNT as u32 + 1]),
        Err(ColoringError::ColorOutOfRange {
            constraint: 2,
            color: GRAPH_COLOR_COUNT as u32 + 1
        })
    );
    assert_eq!(
        validate_coloring(&pairs, &dynamic, &[3, 3, 0]),
        Err(ColoringError::SharedBody {
            first: 0,
            second: 1,
            body: 1,
            color: 3
        })
    );
    // A fixed body may appear any number of times in one color.
    assert_eq!(
        validate_coloring(&[(0, 3), (1, 3), (2, 3)], &dynamic, &[5, 5, 5]),
        Ok(())
    );
    // The largest color index is valid.
    assert_eq!(
        validate_coloring(&pairs, &dynamic, &[GRAPH_COLOR_COUNT as u32 - 1, 0, 1]),
        Ok(())
    );
    assert!(matches!(
        validate_coloring(&[(0, 9)], &dynamic, &[0]),
        Err(ColoringError::BadBody(_))
    ));
    // A constraint of a body with itself does not conflict with itself.
    assert_eq!(validate_coloring(&[(1, 1)], &dynamic, &[0]), Ok(()));
}
