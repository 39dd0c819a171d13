//! The passes on a block: warm start, the solve pass (biased or relax) and restitution, each
//! the scalar kernel of `contact_solver.rs` lane by lane, its branches as masks.

use tumble_geometry::{MAX_MANIFOLD_POINTS, Real};

use super::block::{LaneBlock, LaneBodies, Point};
use super::wide::{F, M, V3};
use crate::PassContext;

/// [`crate::AngularRow`] per lane, rebuilt in the passes from the point's anchors and the
/// bodies' inverse inertias as `prepare_contact` builds it (`AngularRow::new`): four vectors
/// per row and three rows per point would be most of the block, and the passes are bound by
/// the memory they stream more than by arithmetic.
#[derive(Clone, Copy, Debug, Default)]
struct Row {
    arm_a: V3,
    arm_b: V3,
    push_a: V3,
    push_b: V3,
}

impl Row {
    /// The row of direction `d` at point `p`.
    #[inline(always)]
    pub(super) fn new(v: &LaneBodies, p: &Point, d: &V3) -> Row {
        let arm_a = p.anchor_a.cross(d);
        let arm_b = p.anchor_b.cross(d);
        Row {
            arm_a,
            arm_b,
            push_a: v.inverse_inertia_a.mul(&arm_a),
            push_b: v.inverse_inertia_b.mul(&arm_b),
        }
    }
}

/// Velocity of a row: `d . (v_b - v_a) + arm_b . w_b - arm_a . w_a`.
#[inline(always)]
fn row_velocity(v: &LaneBodies, d: &V3, row: &Row) -> F {
    d.dot(&(v.b_linear - v.a_linear)) + row.arm_b.dot(&v.b_angular) - row.arm_a.dot(&v.a_angular)
}

/// Applies `lambda` along a row in the lanes of `m`: `-lambda` on A, `+lambda` on B.
#[inline(always)]
fn apply_row(v: &mut LaneBodies, d: &V3, row: &Row, lambda: F, m: M) {
    let a_linear = v.a_linear - v.inverse_mass_a.cmul(d).scale(lambda);
    let a_angular = v.a_angular - row.push_a.scale(lambda);
    let b_linear = v.b_linear + v.inverse_mass_b.cmul(d).scale(lambda);
    let b_angular = v.b_angular + row.push_b.scale(lambda);
    v.a_linear = m.select3(a_linear, v.a_linear);
    v.a_angular = m.select3(a_angular, v.a_angular);
    v.b_linear = m.select3(b_linear, v.b_linear);
    v.b_angular = m.select3(b_angular, v.b_angular);
}

/// Applies tilt impulses about the two tangents in the lanes of `m`.
#[inline(always)]
fn apply_tilt(v: &mut LaneBodies, push_a: &[V3; 2], push_b: &[V3; 2], lambda: [F; 2], m: M) {
    let a = v.a_angular - (push_a[0].scale(lambda[0]) + push_a[1].scale(lambda[1]));
    let b = v.b_angular + (push_b[0].scale(lambda[0]) + push_b[1].scale(lambda[1]));
    v.a_angular = m.select3(a, v.a_angular);
    v.b_angular = m.select3(b, v.b_angular);
}

/// [`crate::warm_start_contact`] on every lane: each point's three rows as one impulse.
#[inline(always)]
pub(crate) fn warm_start(c: &mut LaneBlock, v: &mut LaneBodies) {
    let (normal, t1, t2) = (c.normal, c.tangent1, c.tangent2);
    let friction = c.friction.gt(F::splat(0.0));
    for i in 0..c.max_points as usize {
        let m = c.point_mask[i];
        let p = c.points[i];
        c.points[i].total_normal_impulse = m.select(
            p.total_normal_impulse + p.normal_impulse,
            p.total_normal_impulse,
        );
        let along = normal.scale(p.normal_impulse);
        let total = along + t1.scale(p.tangent_impulse[0]) + t2.scale(p.tangent_impulse[1]);
        let impulse = friction.select3(total, along);
        let a_linear = v.a_linear - v.inverse_mass_a.cmul(&impulse);
        let a_angular = v.a_angular - v.inverse_inertia_a.mul(&p.anchor_a.cross(&impulse));
        let b_linear = v.b_linear + v.inverse_mass_b.cmul(&impulse);
        let b_angular = v.b_angular + v.inverse_inertia_b.mul(&p.anchor_b.cross(&impulse));
        v.a_linear = m.select3(a_linear, v.a_linear);
        v.a_angular = m.select3(a_angular, v.a_angular);
        v.b_linear = m.select3(b_linear, v.b_linear);
        v.b_angular = m.select3(b_angular, v.b_angular);
    }
    let (push_a, push_b) = tilt_push(c, v);
    apply_tilt(v, &push_a, &push_b, c.tilt_impulse, M::ALL);
}

/// `I_a^-1 t_k` and `I_b^-1 t_k` of the two tangents, as `prepare_contact` computes them.
#[inline(always)]
fn tilt_push(c: &LaneBlock, v: &LaneBodies) -> ([V3; 2], [V3; 2]) {
    let t = [c.tangent1, c.tangent2];
    (
        t.map(|t| v.inverse_inertia_a.mul(&t)),
        t.map(|t| v.inverse_inertia_b.mul(&t)),
    )
}

/// Each point's current separation, from the bodies' deltas.
#[inline(always)]
fn separations(c: &LaneBlock, v: &LaneBodies) -> [F; MAX_MANIFOLD_POINTS] {
    let mut s = [F::default(); MAX_MANIFOLD_POINTS];
    for (i, s) in s.iter_mut().enumerate().take(c.max_points as usize) {
        let p = &c.points[i];
        let ds =
            v.delta_position + v.rotation_b.rotate(&p.anchor_b) - v.rotation_a.rotate(&p.anchor_a);
        *s = p.base_separation + ds.dot(&c.normal);
    }
    s
}

/// The non-penetration rows of every point, in the lanes of `lanes`.
#[inline(always)]
fn normal_rows(
    c: &mut LaneBlock,
    v: &mut LaneBodies,
    ctx: &PassContext,
    s: &[F; MAX_MANIFOLD_POINTS],
    lanes: M,
) {
    let normal = c.normal;
    let zero = F::splat(0.0);
    let one = F::splat(1.0);
    // The soft row's coefficients, the same for every point.
    let soft_rate = c.mass_scale * c.bias_rate;
    let (slop, soft_mass, soft_impulse) = (c.slop, c.mass_scale, c.impulse_scale);
    for i in 0..c.max_points as usize {
        let m = lanes & c.point_mask[i];
        let row = Row::new(v, &c.points[i], &normal);
        let p = &mut c.points[i];
        let s = s[i];
        let speculative = s.gt(zero);
        let (bias, mass_scale, impulse_scale) = if ctx.use_bias {
            let soft = (soft_rate * (s + slop).min(zero)).max(F::splat(-ctx.max_push_out));
            (
                speculative.select(s * F::splat(ctx.inv_h), soft),
                speculative.select(one, soft_mass),
                speculative.select(zero, soft_impulse),
            )
        } else {
            (speculative.select(s * F::splat(ctx.inv_h), zero), one, zero)
        };
        let vn = row_velocity(v, &normal, &row);
        let delta = -p.normal_mass * (mass_scale * vn + bias) - impulse_scale * p.normal_impulse;
        let accumulated = (p.normal_impulse + delta).max(zero);
        let applied = accumulated - p.normal_impulse;
        p.normal_impulse = m.select(accumulated, p.normal_impulse);
        p.total_normal_impulse = m.select(p.total_normal_impulse + applied, p.total_normal_impulse);
        apply_row(v, &normal, &row, applied, m);
    }
}

/// The tilt rows of a face patch, in the lanes of `m`.
#[inline(always)]
fn tilt(c: &mut LaneBlock, v: &mut LaneBodies, m: M) {
    let zero = F::splat(0.0);
    let mut least = F::splat(Real::INFINITY);
    for i in 0..c.max_points as usize {
        least = c.point_mask[i].select(least.min(c.points[i].normal_impulse), least);
    }
    let limit = c.point_count * c.patch_radius * least.max(zero);
    let relative = v.b_angular - v.a_angular;
    let old = c.tilt_impulse;
    let mut new = [
        old[0] - c.tilt_mass[0] * relative.dot(&c.tangent1),
        old[1] - c.tilt_mass[1] * relative.dot(&c.tangent2),
    ];
    let length = (new[0] * new[0] + new[1] * new[1]).sqrt();
    let clamp = length.gt(limit);
    let scale = length.gt(zero).select(limit / length, zero);
    new = [
        clamp.select(new[0] * scale, new[0]),
        clamp.select(new[1] * scale, new[1]),
    ];
    c.tilt_impulse = [m.select(new[0], old[0]), m.select(new[1], old[1])];
    let (push_a, push_b) = tilt_push(c, v);
    apply_tilt(v, &push_a, &push_b, [new[0] - old[0], new[1] - old[1]], m);
}

/// Coulomb friction at every point, in the lanes of `lanes`; returns the lanes whose every
/// point was clamped (the patch slides).
#[inline(always)]
fn friction_rows(c: &mut LaneBlock, v: &mut LaneBodies, lanes: M) -> M {
    let (t1, t2) = (c.tangent1, c.tangent2);
    let friction = c.friction;
    let zero = F::splat(0.0);
    let mut all_slide = M::ALL;
    for i in 0..c.max_points as usize {
        let m = lanes & c.point_mask[i];
        let rows = [
            Row::new(v, &c.points[i], &t1),
            Row::new(v, &c.points[i], &t2),
        ];
        let p = &mut c.points[i];
        let old = p.tangent_impulse;
        let mut new = [
            old[0] - p.tangent_mass[0] * row_velocity(v, &t1, &rows[0]),
            old[1] - p.tangent_mass[1] * row_velocity(v, &t2, &rows[1]),
        ];
        let limit = friction * p.normal_impulse;
        let length = (new[0] * new[0] + new[1] * new[1]).sqrt();
        let clamp = length.gt(limit);
        let scale = length.gt(zero).select(limit / length, zero);
        new = [
            clamp.select(new[0] * scale, new[0]),
            clamp.select(new[1] * scale, new[1]),
        ];
        all_slide = all_slide & (clamp | !m);
        p.tangent_impulse = [m.select(new[0], old[0]), m.select(new[1], old[1])];
        apply_row(v, &t1, &rows[0], new[0] - old[0], m);
        apply_row(v, &t2, &rows[1], new[1] - old[1], m);
    }
    all_slide
}

/// [`crate::solve_contact`] on every lane.
#[inline(always)]
pub(crate) fn solve(c: &mut LaneBlock, v: &mut LaneBodies, ctx: &PassContext) {
    let s = separations(c, v);
    normal_rows(c, v, ctx, &s, M::ALL);
    if c.patch.any() {
        tilt(c, v, c.patch);
    }
    if !ctx.friction {
        return;
    }
    let friction = c.friction.gt(F::splat(0.0));
    if !friction.any() {
        return;
    }
    let all_slide = friction_rows(c, v, friction);
    let again = c.patch & friction & !all_slide;
    if again.any() {
        normal_rows(c, v, ctx, &s, again);
        tilt(c, v, again);
    }
}

/// [`crate::restitution_contact`] on every lane.
#[inline(always)]
pub(crate) fn restitution(c: &mut LaneBlock, v: &mut LaneBodies, threshold: Real) {
    let zero = F::splat(0.0);
    let lanes = !c.restitution.eq(zero);
    if !lanes.any() {
        return;
    }
    let (normal, restitution) = (c.normal, c.restitution);
    let threshold = F::splat(-threshold);
    for i in 0..c.max_points as usize {
        let row = Row::new(v, &c.points[i], &normal);
        let p = &mut c.points[i];
        // Points that did not approach fast enough, or never pushed, keep their impulse.
        let skip = p.relative_velocity.gt(threshold) | p.total_normal_impulse.eq(zero);
        let m = lanes & c.point_mask[i] & !skip;
        let vn = row_velocity(v, &normal, &row);
        let delta = -p.normal_mass * (vn + restitution * p.relative_velocity);
        let accumulated = (p.normal_impulse + delta).max(zero);
        let applied = accumulated - p.normal_impulse;
        p.normal_impulse = m.select(accumulated, p.normal_impulse);
        p.total_normal_impulse = m.select(p.total_normal_impulse + applied, p.total_normal_impulse);
        apply_row(v, &normal, &row, applied, m);
    }
}
