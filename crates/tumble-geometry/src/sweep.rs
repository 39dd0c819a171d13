//! Box-box overlap and box casts (a box moving along a straight line against a still box) by
//! the separating axis test.
//!
//! Method: exact swept SAT. Two boxes are apart exactly when their projections on one of 15
//! axes are apart: the 3 face normals of each and the 9 cross products of an edge direction of
//! one with an edge direction of the other (these are the face normals of their Minkowski
//! difference, a convex polytope). Projected on an axis `L`, the gap between the centres is
//! `c - t w` for a box moving with velocity `v` (`c` the centres' offset along `L`, `w = v . L`)
//! and the projections overlap while `|c - t w| <= r`, `r` the sum of the projection radii: an
//! interval of `t` per axis. The boxes touch from the latest start of these intervals to the
//! earliest end; the time of impact is that latest start (clipped to `[0, max_toi]`), and the
//! normal is the axis it came from. This is the slab test of [`crate::Cuboid::cast_ray`] on the
//! Minkowski difference, so it is exact, not iterative: no conservative advancement, no
//! convergence tolerance.
//!
//! Tolerance: only `f32` rounding. Each axis's offset and radii are sums of a few products of
//! the boxes' coordinates, off by a few ulps of the largest coordinate involved, so the time of
//! impact is off by about `1e-6 * (|centre offset| + sizes) / |v . L|`. An edge pair within
//! `1e-6` rad of parallel ([`PARALLEL_AXIS_NORM_SQ`]) has no axis of its own: the face of the
//! Minkowski difference it would give is a sliver at most `1e-6` times the edges' length wide,
//! and the face axes bound the time of impact as closely as that. Any axis, even a crude one,
//! only ever bounds the time from below, so rounding in an axis' direction never makes a
//! cast pass through a box; only the normal of a hit on such a near-degenerate axis is rough.

use crate::{CastHit, Cuboid, Mat3, Pose, Real, Vec3};

/// Edge-pair axes `a_i x b_j` whose squared length (the squared sine of the angle between the
/// edges) is below this are skipped (see the module docs): `1e-12`, edges within `1e-6` rad.
pub const PARALLEL_AXIS_NORM_SQ: Real = 1e-12;

/// The 15 candidate axes (not normalized; a skipped edge pair is `None`), with the world
/// rotation matrices' columns as the boxes' axes.
fn axes(ra: &Mat3, rb: &Mat3) -> [Option<Vec3>; 15] {
    let mut out = [None; 15];
    for k in 0..3 {
        out[k] = Some(ra.column(k).into_owned());
        out[3 + k] = Some(rb.column(k).into_owned());
    }
    for i in 0..3 {
        for j in 0..3 {
            let axis = ra.column(i).cross(&rb.column(j));
            if axis.norm_squared() >= PARALLEL_AXIS_NORM_SQ {
                out[6 + 3 * i + j] = Some(axis);
            }
        }
    }
    out
}

/// The radius of the projection of a box with rotation `r` and half extents `h` on `axis`.
fn radius(r: &Mat3, h: &Vec3, axis: &Vec3) -> Real {
    (0..3).map(|k| h[k] * r.column(k).dot(axis).abs()).sum()
}

/// True when the closed boxes `a` at `pose_a` and `b` at `pose_b` overlap or touch. The swept
/// test of the module docs at zero velocity: exact up to rounding.
pub fn cuboids_intersect(a: &Cuboid, pose_a: &Pose, b: &Cuboid, pose_b: &Pose) -> bool {
    let ra = pose_a.rotation.to_rotation_matrix().into_inner();
    let rb = pose_b.rotation.to_rotation_matrix().into_inner();
    let offset = pose_b.translation.vector - pose_a.translation.vector;
    axes(&ra, &rb).iter().flatten().all(|l| {
        let r = radius(&ra, &a.half_extents, l) + radius(&rb, &b.half_extents, l);
        // `<=` so touching boxes intersect and a NaN separates.
        offset.dot(l).abs() <= r
    })
}

/// The first time `t` in `[0, max_toi]` at which box `moving`, starting at `pose` and
/// translated by `t * velocity` (no rotation), touches box `target` at `target_pose`. `toi`
/// is in units of `velocity` (seconds for m/s); `normal` is the target's outward unit normal
/// at the touch, pointing towards the moving box. Boxes touching or overlapping at the start
/// hit at `toi = 0` with a zero normal. `None` on a miss, for a negative `max_toi` and for
/// NaN input.
///
/// Exact swept SAT (module docs): the tolerance is `f32` rounding only.
pub fn cast_cuboid(
    moving: &Cuboid,
    pose: &Pose,
    velocity: &Vec3,
    target: &Cuboid,
    target_pose: &Pose,
    max_toi: Real,
) -> Option<CastHit> {
    let ra = pose.rotation.to_rotation_matrix().into_inner();
    let rb = target_pose.rotation.to_rotation_matrix().into_inner();
    let offset = target_pose.translation.vector - pose.translation.vector;
    if max_toi.is_nan() || max_toi < 0.0 {
        return None;
    }
    let (mut enter, mut exit) = (0.0, max_toi);
    let mut entered: Option<(Vec3, Real)> = None;
    for l in axes(&ra, &rb).iter().flatten() {
        let c = offset.dot(l);
        let r = radius(&ra, &moving.half_extents, l) + radius(&rb, &target.half_extents, l);
        let w = velocity.dot(l);
        if w == 0.0 {
            // No motion along this axis: apart on it for good, or no constraint (a NaN is
            // apart).
            let overlapping = c.abs() <= r;
            if !overlapping {
                return None;
            }
            continue;
        }
        // The gap `c - t w` is `r` at (c - r) / w and `-r` at (c + r) / w.
        let (t1, t2) = ((c - r) / w, (c + r) / w);
        if t1.is_nan() || t2.is_nan() {
            return None;
        }
        let (near, far) = if w > 0.0 { (t1, t2) } else { (t2, t1) };
        if near > enter {
            enter = near;
            entered = Some((*l, w));
        }
        if far < exit {
            exit = far;
        }
        // Both are numbers here (NaN times returned above).
        if enter > exit {
            return None;
        }
    }
    let normal = match entered {
        // At the touch the target lies `r` along `sign(w) L` from the moving box, so its face
        // towards the moving box faces `-sign(w) L`.
        Some((l, w)) => -l.normalize() * w.signum(),
        None => Vec3::zeros(),
    };
    Some(CastHit { toi: enter, normal })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Rot;
    use rand::{Rng, SeedableRng};

    fn unit() -> Cuboid {
        Cuboid::new(Vec3::repeat(0.5))
    }

    #[test]
    fn boxes_overlap_when_no_axis_separates_them() {
        let c = unit();
        let at = |x: Real| Pose::translation(x, 0.0, 0.0);
        assert!(cuboids_intersect(&c, &at(0.0), &c, &at(0.9)));
        assert!(
            cuboids_intersect(&c, &at(0.0), &c, &at(1.0)),
            "touching counts"
        );
        assert!(!cuboids_intersect(&c, &at(0.0), &c, &at(1.01)));
        // Two cubes turned 45 degrees about z and y, corner towards corner: apart only along
        // an edge-edge axis would they be missed by the face axes.
        let turned = |x: Real, axis| {
            Pose::from_parts(
                nalgebra::Translation3::new(x, 0.0, 0.0),
                Rot::from_axis_angle(&axis, std::f32::consts::FRAC_PI_4),
            )
        };
        let half_diag = 0.5 * std::f32::consts::SQRT_2;
        let a = turned(0.0, Vec3::z_axis());
        let b = turned(2.0 * half_diag - 0.01, Vec3::y_axis());
        assert!(cuboids_intersect(&c, &a, &c, &b));
        let b = turned(2.0 * half_diag + 0.01, Vec3::y_axis());
        assert!(!cuboids_intersect(&c, &a, &c, &b));
    }

    #[test]
    fn a_box_cast_along_x_stops_at_the_facing_face() {
        let c = unit();
        let start = Pose::identity();
        let target = Pose::translation(5.0, 0.3, -0.2);
        let hit = cast_cuboid(&c, &start, &Vec3::x(), &c, &target, 10.0).expect("hit");
        assert!((hit.toi - 4.0).abs() < 1e-6, "{hit:?}");
        assert!((hit.normal + Vec3::x()).norm() < 1e-6, "{hit:?}");
        // Twice as fast, half the time; too short a cast, or the wrong way, misses.
        let hit = cast_cuboid(&c, &start, &(2.0 * Vec3::x()), &c, &target, 10.0).expect("hit");
        assert!((hit.toi - 2.0).abs() < 1e-6, "{hit:?}");
        assert!(cast_cuboid(&c, &start, &Vec3::x(), &c, &target, 3.9).is_none());
        assert!(cast_cuboid(&c, &start, &-Vec3::x(), &c, &target, 10.0).is_none());
        // Passing above: 1.1 m up clears the target by 0.1 m.
        let above = Pose::translation(0.0, 1.4, 0.0);
        assert!(cast_cuboid(&c, &above, &Vec3::x(), &c, &target, 10.0).is_none());
        // Overlapping at the start: toi 0, no normal.
        let hit = cast_cuboid(&c, &target, &Vec3::x(), &c, &target, 10.0).expect("overlap");
        assert_eq!(hit, CastHit::at_start());
    }

    /// The box cast agrees with bisection on the overlap test, on random pairs: the time of
    /// impact is where the boxes go from apart to overlapping.
    #[test]
    fn box_casts_agree_with_bisection_on_the_overlap_test() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut hits = 0;
        for _ in 0..2000 {
            let mut random_box = || {
                let h = Vec3::from_fn(|_, _| rng.random_range(0.05..1.5));
                let p = Vec3::from_fn(|_, _| rng.random_range(-3.0..3.0));
                let axis = Vec3::from_fn(|_, _| rng.random_range(-1.0..1.0));
                let rot = Rot::from_scaled_axis(axis * 3.0);
                (Cuboid::new(h), Pose::from_parts(p.into(), rot))
            };
            let ((a, pa), (b, pb)) = (random_box(), random_box());
            if cuboids_intersect(&a, &pa, &b, &pb) {
                continue;
            }
            let v = Vec3::from_fn(|_, _| rng.random_range(-1.0..1.0)) * 4.0;
            let at = |t: Real| {
                let mut p = pa;
                p.translation.vector += v * t;
                cuboids_intersect(&a, &p, &b, &pb)
            };
            let hit = cast_cuboid(&a, &pa, &v, &b, &pb, 3.0);
            match hit {
                Some(h) => {
                    hits += 1;
                    // Apart just before, touching at and just after (1e-4 of the cast's
                    // length at most 12 m: well above the rounding of the module docs).
                    assert!(!at(h.toi - 1e-4), "{h:?}");
                    assert!(at(h.toi + 1e-4) || at(h.toi), "{h:?}");
                    assert!((h.normal.norm() - 1.0).abs() < 1e-4 && h.normal.dot(&v) < 0.0);
                    // The moving box's nearest point to the target lies on the target's side
                    // of the touched plane: no part of it is past the normal's plane.
                    let mut p = pa;
                    p.translation.vector += v * h.toi;
                    let deepest = a.support(&p, &-h.normal);
                    let top = b.support(&pb, &h.normal);
                    let gap = (deepest - top).dot(&h.normal);
                    assert!(gap.abs() < 1e-3, "{gap} {h:?}");
                }
                None => {
                    let samples = (0..=300).map(|k| k as Real * 0.01);
                    assert!(samples.into_iter().all(|t| !at(t)), "missed a hit");
                }
            }
        }
        assert!(hits > 100, "{hits} hits");
    }
}
