//! Closest points of two segments in 3D, robust for parallel and zero-length segments.
//!
//! The unclamped minimiser of `|P(s) - Q(t)|^2` solves a 2x2 linear system whose determinant is
//! `|d1 x d2|^2`; it is computed from the cross product rather than as `a e - b^2`, which loses
//! every digit to cancellation when the segments are nearly parallel.

use crate::{Point3, Real};

/// Below this ratio of squared lengths a segment is treated as a point: its direction carries no
/// digit that survives `f32` rounding of the other segment's coordinates.
pub const DEGENERATE_LENGTH_RATIO: Real = Real::EPSILON;

/// Below this squared sine of the angle between them (1e-3 rad), two segments are treated as
/// parallel: the closest pair is then a whole interval and we return the middle of the overlap,
/// which moves continuously as the segments slide.
pub const PARALLEL_SIN_SQ: Real = 1e-6;

/// The closest points of two segments and their parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentClosestPoints {
    /// Parameter on the first segment, in `[0, 1]` (0 at its start).
    pub s: Real,
    /// Parameter on the second segment, in `[0, 1]`.
    pub t: Real,
    /// The closest point on the first segment.
    pub point_a: Point3,
    /// The closest point on the second segment.
    pub point_b: Point3,
}

impl SegmentClosestPoints {
    /// Distance between the two closest points.
    pub fn distance(&self) -> Real {
        (self.point_b - self.point_a).norm()
    }
}

/// Closest points of segment `a0 -> a1` and segment `b0 -> b1`.
///
/// Zero-length segments act as points; parallel segments return the middle of the interval where
/// their projections overlap (or the nearest end points when they do not overlap).
pub fn closest_points_segments(
    a0: &Point3,
    a1: &Point3,
    b0: &Point3,
    b1: &Point3,
) -> SegmentClosestPoints {
    let d1 = a1 - a0;
    let d2 = b1 - b0;
    let r = a0 - b0;
    let a = d1.norm_squared();
    let e = d2.norm_squared();
    let f = d2.dot(&r);
    let a_is_point = a <= DEGENERATE_LENGTH_RATIO * (a + e);
    let b_is_point = e <= DEGENERATE_LENGTH_RATIO * (a + e);

    let (s, t) = if a_is_point && b_is_point {
        (0.0, 0.0)
    } else if a_is_point {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else if b_is_point {
        (((-d1.dot(&r)) / a).clamp(0.0, 1.0), 0.0)
    } else {
        let b = d1.dot(&d2);
        let c = d1.dot(&r);
        let denom = d1.cross(&d2).norm_squared();
        let s = if denom > PARALLEL_SIN_SQ * a * e {
            ((b * f - c * e) / denom).clamp(0.0, 1.0)
        } else {
            parallel_overlap_middle(-c / a, (b - c) / a)
        };
        // The best t for this s, then the best s for a clamped t.
        let t = (b * s + f) / e;
        if t < 0.0 {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else if t > 1.0 {
            (((b - c) / a).clamp(0.0, 1.0), 1.0)
        } else {
            (s, t)
        }
    };
    SegmentClosestPoints {
        s,
        t,
        point_a: a0 + d1 * s,
        point_b: b0 + d2 * t,
    }
}

/// For parallel segments: the second segment's end points project to parameters `s0` and `s1` on
/// the first; the middle of their overlap with `[0, 1]`, or the nearer end when they miss it.
fn parallel_overlap_middle(s0: Real, s1: Real) -> Real {
    let lo = s0.min(s1).max(0.0);
    let hi = s0.max(s1).min(1.0);
    if lo <= hi {
        0.5 * (lo + hi)
    } else if s0.max(s1) < 0.0 {
        0.0
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: Real, y: Real, z: Real) -> Point3 {
        Point3::new(x, y, z)
    }

    #[test]
    fn crossing_segments_meet_at_their_interior_closest_points() {
        // x-axis segment at z = 0 and y-axis segment at z = 1: closest pair (0.5,0,0)-(0.5,0,1).
        let c = closest_points_segments(
            &p(0.0, 0.0, 0.0),
            &p(1.0, 0.0, 0.0),
            &p(0.5, -1.0, 1.0),
            &p(0.5, 1.0, 1.0),
        );
        assert_eq!((c.s, c.t), (0.5, 0.5));
        assert_eq!(c.point_a, p(0.5, 0.0, 0.0));
        assert_eq!(c.point_b, p(0.5, 0.0, 1.0));
        assert_eq!(c.distance(), 1.0);
    }

    #[test]
    fn clamped_ends_when_the_infinite_lines_meet_outside_the_segments() {
        // The lines cross at x = 3, beyond the first segment's end: the first clamps to its end
        // (1,0,0) and the second moves to the point nearest to it.
        let c = closest_points_segments(
            &p(0.0, 0.0, 0.0),
            &p(1.0, 0.0, 0.0),
            &p(3.0, -1.0, 0.5),
            &p(3.0, 1.0, 0.5),
        );
        assert_eq!(c.s, 1.0);
        assert_eq!(c.point_b, p(3.0, 0.0, 0.5));
        assert!((c.distance() - (4.0_f32 + 0.25).sqrt()).abs() < 1e-6);
    }

    #[test]
    fn parallel_overlapping_segments_give_the_middle_of_the_overlap() {
        // [0, 4] and [1, 6] on parallel lines one unit apart: the overlap is [1, 4], middle 2.5.
        let c = closest_points_segments(
            &p(0.0, 0.0, 0.0),
            &p(4.0, 0.0, 0.0),
            &p(6.0, 1.0, 0.0),
            &p(1.0, 1.0, 0.0),
        );
        assert_eq!(c.point_a, p(2.5, 0.0, 0.0));
        assert_eq!(c.point_b, p(2.5, 1.0, 0.0));
        assert_eq!(c.distance(), 1.0);
    }

    #[test]
    fn parallel_disjoint_segments_pair_the_nearest_ends() {
        let c = closest_points_segments(
            &p(0.0, 0.0, 0.0),
            &p(1.0, 0.0, 0.0),
            &p(3.0, 1.0, 0.0),
            &p(5.0, 1.0, 0.0),
        );
        assert_eq!(c.point_a, p(1.0, 0.0, 0.0));
        assert_eq!(c.point_b, p(3.0, 1.0, 0.0));
        let behind = closest_points_segments(
            &p(0.0, 0.0, 0.0),
            &p(1.0, 0.0, 0.0),
            &p(-3.0, 1.0, 0.0),
            &p(-2.0, 1.0, 0.0),
        );
        assert_eq!(behind.point_a, p(0.0, 0.0, 0.0));
        assert_eq!(behind.point_b, p(-2.0, 1.0, 0.0));
    }

    #[test]
    fn a_zero_length_segment_acts_as_a_point() {
        let c = closest_points_segments(
            &p(0.5, 2.0, 0.0),
            &p(0.5, 2.0, 0.0),
            &p(0.0, 0.0, 0.0),
            &p(1.0, 0.0, 0.0),
        );
        assert_eq!(c.point_b, p(0.5, 0.0, 0.0));
        assert_eq!(c.distance(), 2.0);
        let both = closest_points_segments(
            &p(1.0, 1.0, 1.0),
            &p(1.0, 1.0, 1.0),
            &p(1.0, 1.0, 4.0),
            &p(1.0, 1.0, 4.0),
        );
        assert_eq!(both.distance(), 3.0);
        assert!(both.s.is_finite() && both.t.is_finite());
    }

    #[test]
    fn nearly_parallel_segments_stay_finite_and_no_farther_than_an_end_point_pair() {
        // A tilt of 1e-6 rad: inside the parallel band, where a naive solve divides by ~1e-12.
        let c = closest_points_segments(
            &p(0.0, 0.0, 0.0),
            &p(1.0, 0.0, 0.0),
            &p(0.0, 1.0, 0.0),
            &p(1.0, 1.0, 1e-6),
        );
        assert!(
            c.point_a
                .coords
                .iter()
                .chain(c.point_b.coords.iter())
                .all(|v| v.is_finite())
        );
        // The true minimum is within 1e-6 of 1; rounding aside, we must not do worse.
        assert!((c.distance() - 1.0).abs() < 1e-5);
    }

    /// The exact minimum distance of two segments, in f64: a convex quadratic over the unit
    /// square has its minimum at the interior critical point or on one of the four edges, and
    /// on an edge it is the clamped 1D minimiser.
    fn reference_distance(a0: &Point3, a1: &Point3, b0: &Point3, b1: &Point3) -> f64 {
        let v = |q: &Point3| [q.x as f64, q.y as f64, q.z as f64];
        let (a0, a1, b0, b1) = (v(a0), v(a1), v(b0), v(b1));
        let sub = |x: [f64; 3], y: [f64; 3]| [x[0] - y[0], x[1] - y[1], x[2] - y[2]];
        let dot = |x: [f64; 3], y: [f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
        let at =
            |o: [f64; 3], d: [f64; 3], s: f64| [o[0] + s * d[0], o[1] + s * d[1], o[2] + s * d[2]];
        let (d1, d2) = (sub(a1, a0), sub(b1, b0));
        let dist = |s: f64, t: f64| {
            let w = sub(at(a0, d1, s), at(b0, d2, t));
            dot(w, w).sqrt()
        };
        // The best parameter along a segment of direction `d` from `o` for the point `q`.
        let nearest = |o: [f64; 3], d: [f64; 3], q: [f64; 3]| {
            let len2 = dot(d, d);
            if len2 == 0.0 {
                0.0
            } else {
                (dot(sub(q, o), d) / len2).clamp(0.0, 1.0)
            }
        };
        let mut best = f64::INFINITY;
        for s in [0.0, 1.0] {
            best = best.min(dist(s, nearest(b0, d2, at(a0, d1, s))));
        }
        for t in [0.0, 1.0] {
            best = best.min(dist(nearest(a0, d1, at(b0, d2, t)), t));
        }
        let (a, b, e) = (dot(d1, d1), dot(d1, d2), dot(d2, d2));
        let r = sub(a0, b0);
        let (c, f) = (dot(d1, r), dot(d2, r));
        let det = a * e - b * b;
        if det > 1e-12 * a * e {
            let s = (b * f - c * e) / det;
            let t = (a * f - b * c) / det;
            if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
                best = best.min(dist(s, t));
            }
        }
        best
    }

    #[test]
    fn random_segments_match_the_exact_minimum_distance() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let point = |rng: &mut rand_chacha::ChaCha8Rng| {
            p(
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
            )
        };
        let mut interior = 0;
        for case in 0..4000 {
            let (a0, b0) = (point(&mut rng), point(&mut rng));
            // A quarter of the cases are parallel (the second segment a shifted, scaled copy of
            // the first) and a tenth have a zero-length segment: the special branches.
            let a1 = point(&mut rng);
            let b1 = match case % 10 {
                0 => b0,
                1 | 2 => b0 + (a1 - a0) * rng.random_range(-1.5..1.5),
                _ => point(&mut rng),
            };
            let a1 = if case % 20 == 5 { a0 } else { a1 };
            let c = closest_points_segments(&a0, &a1, &b0, &b1);
            // The points lie on their segments at the reported parameters.
            assert!(
                (0.0..=1.0).contains(&c.s) && (0.0..=1.0).contains(&c.t),
                "case {case}: {c:?}"
            );
            assert!(
                (c.point_a - (a0 + (a1 - a0) * c.s)).norm() < 1e-5,
                "case {case}"
            );
            assert!(
                (c.point_b - (b0 + (b1 - b0) * c.t)).norm() < 1e-5,
                "case {case}"
            );
            // And they are the closest pair: f32 coordinates of size 4 carry about 1e-6 of
            // round-off per operation; 2e-5 m is a few dozen of them and far below any mutation.
            let exact = reference_distance(&a0, &a1, &b0, &b1);
            assert!(
                (c.distance() as f64 - exact).abs() < 2e-5,
                "case {case}: distance {} but the exact minimum is {exact}",
                c.distance()
            );
            if c.s > 0.0 && c.s < 1.0 && c.t > 0.0 && c.t < 1.0 {
                interior += 1;
            }
        }
        // The interior solve must have been exercised, not only the clamped branches.
        assert!(interior > 300, "only {interior} interior cases");
    }

    #[test]
    fn parallel_segments_that_miss_pick_the_nearer_end_on_either_side() {
        // The second segment lies beyond the first's end (s > 1) or before its start (s < 0).
        let after = closest_points_segments(
            &p(0.0, 0.0, 0.0),
            &p(1.0, 0.0, 0.0),
            &p(2.0, 1.0, 0.0),
            &p(3.0, 1.0, 0.0),
        );
        assert_eq!((after.s, after.t), (1.0, 0.0));
        let before = closest_points_segments(
            &p(0.0, 0.0, 0.0),
            &p(1.0, 0.0, 0.0),
            &p(-3.0, 1.0, 0.0),
            &p(-2.0, 1.0, 0.0),
        );
        assert_eq!((before.s, before.t), (0.0, 1.0));
        // Reversed direction of the second segment: same ends, parameters swapped.
        let reversed = closest_points_segments(
            &p(0.0, 0.0, 0.0),
            &p(1.0, 0.0, 0.0),
            &p(-2.0, 1.0, 0.0),
            &p(-3.0, 1.0, 0.0),
        );
        assert_eq!((reversed.s, reversed.t), (0.0, 0.0));
    }

    #[test]
    fn a_short_skew_segment_takes_the_interior_solve_whichever_side_it_is_on() {
        // A 1 m segment along x and a 1 cm one at y = 1 along (1, 0, 1): skew lines 45 degrees
        // apart, far outside the parallel band whatever the lengths. The closest pair is at
        // s = 0.3 (where the short one crosses z = 0) and t = 0; the overlap middle of the
        // parallel branch would give s = 0.3035.
        let (a0, a1) = (p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0));
        let (b0, b1) = (p(0.3, 1.0, 0.0), p(0.307, 1.0, 0.007));
        let c = closest_points_segments(&a0, &a1, &b0, &b1);
        assert!((c.s - 0.3).abs() < 1e-5 && c.t.abs() < 1e-5, "{c:?}");
        let c = closest_points_segments(&b0, &b1, &a0, &a1);
        assert!(c.s.abs() < 1e-5 && (c.t - 0.3).abs() < 1e-5, "{c:?}");
    }

    #[test]
    fn parallel_overlap_is_measured_in_the_first_segments_parameter() {
        // A 2 m segment and a parallel 1 m one over x in [0.5, 1.5]: the second projects to
        // s in [0.25, 0.75] on the first, so the middle of the overlap is s = 0.5 (x = 1), and
        // the second segment's point nearest to it is its middle.
        let c = closest_points_segments(
            &p(0.0, 0.0, 0.0),
            &p(2.0, 0.0, 0.0),
            &p(0.5, 1.0, 0.0),
            &p(1.5, 1.0, 0.0),
        );
        assert_eq!((c.s, c.t), (0.5, 0.5));
        assert_eq!(c.point_a, p(1.0, 0.0, 0.0));
    }
}
