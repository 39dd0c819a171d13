//! Reduction of a planar contact polygon to at most four points (the thesis's Algorithm 8).
//!
//! 1. the deepest point (the support point along the contact normal);
//! 2. the point farthest from it;
//! 3. the point making the largest triangle with the first two;
//! 4. the point adding the most area outside that triangle, i.e. the largest quadrilateral.
//!
//! Areas are measured in the plane perpendicular to the normal (`(u x v) . n`), so the points
//! need only be flat up to a shift along the normal, as manifold midpoints are.
//! The kept points keep their ids and their order in the input, so a convex polygon stays convex
//! and in order after reduction.

use crate::{ContactPoint, MAX_MANIFOLD_POINTS, Manifold, Point3, Real, Vec3};

/// Twice the signed area of triangle `(a, b, c)` seen along `normal` (positive when counter-clockwise).
fn twice_signed_area(a: &Point3, b: &Point3, c: &Point3, normal: &Vec3) -> Real {
    (b - a).cross(&(c - a)).dot(normal)
}

/// Index of the first point maximising `score` (first wins ties, so the choice is reproducible).
fn argmax(points: &[ContactPoint], mut score: impl FnMut(&ContactPoint) -> Real) -> usize {
    let mut best = 0;
    let mut best_score = Real::NEG_INFINITY;
    for (i, p) in points.iter().enumerate() {
        let s = score(p);
        if s > best_score {
            best = i;
            best_score = s;
        }
    }
    best
}

/// The indices (ascending, into `points`) of at most four points spanning the largest area,
/// and how many of the four slots are used.
///
/// Four or fewer input points are all kept. Degenerate inputs (all points on one spot or one
/// line) keep fewer points rather than duplicates.
pub fn select_four(
    points: &[ContactPoint],
    normal: &Vec3,
) -> ([usize; MAX_MANIFOLD_POINTS], usize) {
    let mut chosen = [0usize; MAX_MANIFOLD_POINTS];
    if points.len() <= MAX_MANIFOLD_POINTS {
        for (i, slot) in chosen.iter_mut().enumerate().take(points.len()) {
            *slot = i;
        }
        return (chosen, points.len());
    }
    let i0 = argmax(points, |p| p.depth);
    let p0 = points[i0].position;
    let i1 = argmax(points, |p| (p.position - p0).norm_squared());
    let p1 = points[i1].position;
    let i2 = argmax(points, |p| {
        twice_signed_area(&p0, &p1, &p.position, normal).abs()
    });
    let p2 = points[i2].position;
    // Orient the triangle counter-clockwise; a point outside edge (u, v) then has a negative
    // signed area with it, and that area is what the fourth point adds to the triangle.
    let orientation = twice_signed_area(&p0, &p1, &p2, normal).signum();
    let added = |p: &ContactPoint| {
        let q = p.position;
        let outside = |u: &Point3, v: &Point3| -orientation * twice_signed_area(u, v, &q, normal);
        outside(&p0, &p1)
            .max(outside(&p1, &p2))
            .max(outside(&p2, &p0))
    };
    let i3 = argmax(points, added);

    let mut len = 0;
    let mut push = |i: usize, area: Real| {
        if area > 0.0 && !chosen[..len].contains(&i) {
            chosen[len] = i;
            len += 1;
        }
    };
    push(i0, 1.0);
    push(i1, (p1 - p0).norm_squared());
    push(i2, twice_signed_area(&p0, &p1, &p2, normal).abs());
    push(i3, added(&points[i3]));
    chosen[..len].sort_unstable();
    (chosen, len)
}

/// Fills `manifold` (its normal already set) with at most four of `points`, chosen by
/// [`select_four`]; the points keep their positions, depths and ids.
pub fn reduce_into(points: &[ContactPoint], manifold: &mut Manifold) {
    let (chosen, len) = select_four(points, &manifold.normal);
    manifold.len = 0;
    for &i in &chosen[..len] {
        manifold.push(points[i]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(x: Real, y: Real, depth: Real, id: u32) -> ContactPoint {
        ContactPoint {
            position: Point3::new(x, y, 0.0),
            depth,
            id,
        }
    }

    /// Area of the convex polygon through `points` taken in the given (convex) order.
    fn area(points: &[ContactPoint]) -> Real {
        (0..points.len())
            .map(|k| {
                let (p, q) = (points[k].position, points[(k + 1) % points.len()].position);
                p.x * q.y - q.x * p.y
            })
            .sum::<Real>()
            .abs()
            * 0.5
    }

    fn octagon() -> Vec<ContactPoint> {
        (0..8)
            .map(|k| {
                let angle = k as Real * std::f32::consts::FRAC_PI_4;
                // Slightly different depths so the deepest point is vertex 3, not a tie.
                point(
                    angle.cos(),
                    angle.sin(),
                    0.01 + 0.001 * (k == 3) as u32 as Real,
                    100 + k,
                )
            })
            .collect()
    }

    #[test]
    fn a_regular_octagon_reduces_to_its_largest_inscribed_quadrilateral() {
        let points = octagon();
        let mut m = Manifold {
            normal: Vec3::z(),
            ..Default::default()
        };
        reduce_into(&points, &mut m);
        assert_eq!(m.len, 4);
        // The largest quadrilateral in a regular octagon of circumradius 1 is the square on every
        // other vertex, area 2 (the octagon itself has 2 sqrt 2). f32 trigonometry: 1e-5.
        assert!(
            (area(m.points()) - 2.0).abs() < 1e-5,
            "area {}",
            area(m.points())
        );
        // It starts from the deepest vertex, so the square is vertices 1, 3, 5, 7; the ids survive.
        let ids: Vec<u32> = m.points().iter().map(|p| p.id).collect();
        assert_eq!(ids, vec![101, 103, 105, 107]);
    }

    #[test]
    fn four_or_fewer_points_pass_through_unchanged() {
        let points = vec![
            point(0.0, 0.0, 0.1, 1),
            point(1.0, 0.0, 0.2, 2),
            point(0.0, 1.0, 0.3, 3),
        ];
        let (chosen, len) = select_four(&points, &Vec3::z());
        assert_eq!(&chosen[..len], &[0, 1, 2]);
    }

    #[test]
    fn the_deepest_point_is_always_kept() {
        // A hexagon whose deepest vertex (index 4) is not on the largest quadrilateral found
        // from vertex 0: it must still be the first choice.
        let points: Vec<_> = (0..6)
            .map(|k| {
                let angle = k as Real * std::f32::consts::FRAC_PI_3;
                point(angle.cos(), angle.sin(), if k == 4 { 0.5 } else { 0.1 }, k)
            })
            .collect();
        let (chosen, len) = select_four(&points, &Vec3::z());
        assert!(chosen[..len].contains(&4));
        assert_eq!(len, 4);
    }

    #[test]
    fn collinear_and_coincident_points_do_not_produce_duplicates() {
        let line: Vec<_> = (0..6).map(|k| point(k as Real, 0.0, 0.0, k)).collect();
        let (chosen, len) = select_four(&line, &Vec3::z());
        // Two end points carry the whole segment; a third collinear one adds no area.
        assert_eq!(len, 2);
        assert_eq!(&chosen[..len], &[0, 5]);
        let same: Vec<_> = (0..6).map(|k| point(1.0, 1.0, 0.0, k)).collect();
        assert_eq!(select_four(&same, &Vec3::z()).1, 1);
    }

    #[test]
    fn the_reduced_area_is_at_least_half_of_random_convex_polygons() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for _ in 0..500 {
            // A convex polygon: 5 to 8 sorted angles on an ellipse with random axes.
            let n = rng.random_range(5..=8);
            let mut angles: Vec<Real> = (0..n)
                .map(|_| rng.random_range(0.0..std::f32::consts::TAU))
                .collect();
            angles.sort_by(Real::total_cmp);
            let (rx, ry) = (rng.random_range(0.1..3.0), rng.random_range(0.1..3.0));
            let points: Vec<_> = angles
                .iter()
                .enumerate()
                .map(|(k, a)| {
                    point(
                        rx * a.cos(),
                        ry * a.sin(),
                        rng.random_range(-0.1..0.1),
                        k as u32,
                    )
                })
                .collect();
            let (chosen, len) = select_four(&points, &Vec3::z());
            let kept: Vec<_> = chosen[..len].iter().map(|&i| points[i]).collect();
            // The ascending indices keep the polygon's cyclic order, so the shoelace area of the
            // kept points is their convex hull's. One half is the bound the narrow phase promises.
            assert!(
                area(&kept) >= 0.5 * area(&points),
                "{} of {}",
                area(&kept),
                area(&points)
            );
        }
    }

    #[test]
    fn ties_go_to_the_first_point_in_input_order() {
        // A symmetric hexagon with integer corners (exact in f32), all points equally deep.
        // By hand, first-wins: the deepest is point 0 at (2, 0); the farthest from it is
        // point 3 at (-2, 0); points 1, 2, 4, 5 are all 2 off that line, so point 1 wins;
        // outside triangle (0, 3, 1), points 4 and 5 add twice-area 8 and point 2 only 4, so
        // point 4. Last-wins ties would start from point 5 and keep another set.
        let corners = [
            (2.0, 0.0),
            (1.0, 2.0),
            (-1.0, 2.0),
            (-2.0, 0.0),
            (-1.0, -2.0),
            (1.0, -2.0),
        ];
        let hexagon: Vec<ContactPoint> = corners
            .iter()
            .enumerate()
            .map(|(k, &(x, y))| point(x, y, 0.01, k as u32))
            .collect();
        let (chosen, len) = select_four(&hexagon, &Vec3::z());
        assert_eq!(&chosen[..len], &[0, 1, 3, 4]);
    }

    #[test]
    fn collinear_points_keep_only_the_two_ends_wherever_they_sit_in_the_input() {
        // The ends (x = 0 and x = 1) sit in the middle of the list and the deepest point is an
        // end: the zero-area third and fourth choices must not add a middle point.
        let xs = [0.3, 0.5, 0.0, 1.0, 0.7, 0.2];
        let points: Vec<ContactPoint> = xs
            .iter()
            .enumerate()
            .map(|(i, &x)| point(x, 0.0, if i == 3 { 0.02 } else { 0.01 }, i as u32))
            .collect();
        let (chosen, len) = select_four(&points, &Vec3::z());
        assert_eq!(&chosen[..len], &[2, 3]);
    }
}
