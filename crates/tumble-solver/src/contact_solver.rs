//! The per-constraint kernels of the solve stage: warm start, one (biased or relaxed) pass of
//! sequential impulses over a manifold's points, and the restitution pass.
//!
//! Each function reads and writes only the constraint and the two body states it is given, so
//! the same code serves the sequential order and the colored (parallel) order.

use tumble_geometry::{Real, Vec3};

use crate::{AngularRow, BodyState, ContactConstraint};

/// Per-pass values shared by every constraint.
#[derive(Clone, Copy, Debug)]
pub struct PassContext {
    /// `1 / h` for the substep, used by speculative points to close the gap in one substep.
    pub inv_h: Real,
    /// Feed position error back (solve) or not (relax).
    pub use_bias: bool,
    /// Cap on the separation speed the position feedback may request, m/s.
    pub max_push_out: Real,
    /// Solve the friction rows and a face patch's second visit; without, the pass ends after
    /// the normal and tilt rows ([`crate::FrictionPasses::RelaxOnly`]'s biased passes).
    pub friction: bool,
}

/// `a` when it is greater than `b`, else `b`: the clamps of the passes, written as a compare
/// and a select so that the scalar and the lane kernels (`lanes/`) agree to the bit.
/// `f32::max` leaves the sign of a zero result open (`max(-0.0, 0.0)` may be either), and
/// the compiler's scalar and vector forms of it need not choose alike.
#[inline(always)]
pub(crate) fn max_of(a: Real, b: Real) -> Real {
    if a > b { a } else { b }
}

/// `a` when it is less than `b`, else `b` (see [`max_of`]).
#[inline(always)]
pub(crate) fn min_of(a: Real, b: Real) -> Real {
    if a < b { a } else { b }
}

/// Velocity of row `d` (with angular part `row`): `d . (v_b - v_a) + arm_b . w_b - arm_a . w_a`.
#[inline]
fn row_velocity(a: &BodyState, b: &BodyState, d: &Vec3, row: &AngularRow) -> Real {
    d.dot(&(b.linear_velocity - a.linear_velocity)) + row.arm_b.dot(&b.angular_velocity)
        - row.arm_a.dot(&a.angular_velocity)
}

/// Applies impulse `lambda` along row `d`: `-lambda` on A, `+lambda` on B.
#[inline]
fn apply_row(
    c: &ContactConstraint,
    a: &mut BodyState,
    b: &mut BodyState,
    d: &Vec3,
    row: &AngularRow,
    lambda: Real,
) {
    a.linear_velocity -= c.inverse_mass_a.component_mul(d) * lambda;
    a.angular_velocity -= row.push_a * lambda;
    b.linear_velocity += c.inverse_mass_b.component_mul(d) * lambda;
    b.angular_velocity += row.push_b * lambda;
}

/// Re-applies the accumulated impulses (normal, friction, tilt) at the start of a substep.
///
/// A point's three rows act at the same anchors, so they are applied as one impulse
/// `P = (n lambda_n + t1 lambda_1) + t2 lambda_2`: each body turns by `I^-1 (r x P)`, the sum
/// of the three rows' turns up to rounding. The lane kernel, which rebuilds a row's angular
/// terms from the anchors, so does one cross product and one matrix product per body instead
/// of three; this scalar reference does the same operations to keep its bits. The GPU's
/// `warm_start_points` (contact_math.wgsl) writes the same sum in the same order (it also adds
/// a frictionless contact's zero tangent terms, and may fuse multiply-adds).
pub fn warm_start_contact(c: &mut ContactConstraint, a: &mut BodyState, b: &mut BodyState) {
    // Without friction only the normal row carries an impulse.
    let frictional = c.friction > 0.0;
    for i in 0..c.point_count as usize {
        let cp = c.points[i];
        c.points[i].total_normal_impulse += cp.normal_impulse;
        let mut impulse = c.normal * cp.normal_impulse;
        if frictional {
            impulse =
                impulse + c.tangent1 * cp.tangent_impulse[0] + c.tangent2 * cp.tangent_impulse[1];
        }
        a.linear_velocity -= c.inverse_mass_a.component_mul(&impulse);
        a.angular_velocity -= c.inverse_inertia_a * cp.anchor_a.cross(&impulse);
        b.linear_velocity += c.inverse_mass_b.component_mul(&impulse);
        b.angular_velocity += c.inverse_inertia_b * cp.anchor_b.cross(&impulse);
    }
    apply_tilt(c, a, b, c.tilt_impulse);
}

/// Applies tilt impulses `lambda` about the two tangents: `-` on A, `+` on B.
#[inline]
fn apply_tilt(c: &ContactConstraint, a: &mut BodyState, b: &mut BodyState, lambda: [Real; 2]) {
    a.angular_velocity -= c.tilt_push_a[0] * lambda[0] + c.tilt_push_a[1] * lambda[1];
    b.angular_velocity += c.tilt_push_b[0] * lambda[0] + c.tilt_push_b[1] * lambda[1];
}

/// The tilt rows of a face patch: no relative rotation about the two tangents, within the
/// torque the patch can add without unloading any point.
///
/// The normal rows already carry a patch's torque through the spread of their impulses, but
/// with one pass per substep they converge slowly for tall stacks, and with soft contacts a
/// column of them leans and buckles. The tilt rows solve the patch's rotation as one rigid 2D
/// row. Shifting load across a patch of `n` points and inscribed radius `r` can add a torque of
/// about `n * r * min(lambda_i)` before the least loaded point lets go, so that is the bound:
/// a box whose far edge has lifted (a domino tipping over its front edge) gets no tilt torque,
/// and tips exactly as its normal rows dictate.
fn solve_tilt(c: &mut ContactConstraint, a: &mut BodyState, b: &mut BodyState) {
    let points = &c.points[..c.point_count as usize];
    let least = points
        .iter()
        .map(|p| p.normal_impulse)
        .fold(Real::INFINITY, min_of);
    let limit = points.len() as Real * c.patch_radius * max_of(least, 0.0);
    let (t1, t2) = (c.tangent1, c.tangent2);
    let relative = b.angular_velocity - a.angular_velocity;
    let old = c.tilt_impulse;
    let mut new = [
        old[0] - c.tilt_mass[0] * relative.dot(&t1),
        old[1] - c.tilt_mass[1] * relative.dot(&t2),
    ];
    let length = (new[0] * new[0] + new[1] * new[1]).sqrt();
    if length > limit {
        let scale = if length > 0.0 { limit / length } else { 0.0 };
        new = [new[0] * scale, new[1] * scale];
    }
    c.tilt_impulse = new;
    apply_tilt(c, a, b, [new[0] - old[0], new[1] - old[1]]);
}

/// Non-penetration rows of every point. The current separation `s` is rebuilt from the
/// bodies' deltas. A point still apart (`s > 0`) is speculative: bodies may approach by at most
/// `s` this substep (`bias = s / h`). An overlapping point gets, when `use_bias`, the position
/// feedback `max(mass_scale * bias_rate * min(s + slop, 0), -max_push_out)` with the soft mass
/// and impulse scales; relax passes use the rigid row with no feedback.
fn solve_normal_rows(
    c: &mut ContactConstraint,
    a: &mut BodyState,
    b: &mut BodyState,
    ctx: &PassContext,
) {
    let normal = c.normal;
    let dp = b.delta_position - a.delta_position;
    for i in 0..c.point_count as usize {
        let cp = c.points[i];
        let ds = dp + b.delta_rotation * cp.anchor_b - a.delta_rotation * cp.anchor_a;
        let s = cp.base_separation + ds.dot(&normal);
        let (bias, mass_scale, impulse_scale) = if s > 0.0 {
            (s * ctx.inv_h, 1.0, 0.0)
        } else if ctx.use_bias {
            let soft = c.softness;
            let bias = max_of(
                soft.mass_scale * soft.bias_rate * min_of(s + c.slop, 0.0),
                -ctx.max_push_out,
            );
            (bias, soft.mass_scale, soft.impulse_scale)
        } else {
            (0.0, 1.0, 0.0)
        };
        let vn = row_velocity(a, b, &normal, &cp.normal_row);
        let delta = -cp.normal_mass * (mass_scale * vn + bias) - impulse_scale * cp.normal_impulse;
        let accumulated = max_of(cp.normal_impulse + delta, 0.0);
        let applied = accumulated - cp.normal_impulse;
        c.points[i].normal_impulse = accumulated;
        c.points[i].total_normal_impulse += applied;
        apply_row(c, a, b, &normal, &cp.normal_row, applied);
    }
}

/// Coulomb friction: the two tangent rows of a point update together and the tangential
/// impulse vector is clamped to the disc of radius `mu * normal impulse` (isotropic). Returns
/// true when every point's impulse was clamped: the whole patch slides.
fn solve_friction_rows(c: &mut ContactConstraint, a: &mut BodyState, b: &mut BodyState) -> bool {
    let (t1, t2) = (c.tangent1, c.tangent2);
    let mut all_slide = true;
    for i in 0..c.point_count as usize {
        let cp = c.points[i];
        let old = cp.tangent_impulse;
        let mut new = [
            old[0] - cp.tangent_mass[0] * row_velocity(a, b, &t1, &cp.tangent_rows[0]),
            old[1] - cp.tangent_mass[1] * row_velocity(a, b, &t2, &cp.tangent_rows[1]),
        ];
        let limit = c.friction * cp.normal_impulse;
        let length = (new[0] * new[0] + new[1] * new[1]).sqrt();
        if length > limit {
            let scale = if length > 0.0 { limit / length } else { 0.0 };
            new = [new[0] * scale, new[1] * scale];
        } else {
            all_slide = false;
        }
        c.points[i].tangent_impulse = new;
        apply_row(c, a, b, &t1, &cp.tangent_rows[0], new[0] - old[0]);
        apply_row(c, a, b, &t2, &cp.tangent_rows[1], new[1] - old[1]);
    }
    all_slide
}

/// One pass over the constraint: non-penetration, the tilt rows of a face patch, Coulomb
/// friction, then for a face patch that does not slide at every point its non-penetration and
/// tilt rows once more. Without `ctx.friction` the pass ends after the first tilt rows.
///
/// The friction rows act at the points, below body B's centre and above body A's, so their
/// impulses turn the bodies and undo what the tilt rows just held. Left so until the next
/// pass, that turn feeds a sway of piled boxes that one biased pass per substep never damps:
/// the 6 x 6 pile three cubes high of docs/solver.md ("Piles that keep rocking") rocked at
/// about 25 Hz for as long as it ran. Solving the patch's normal and tilt rows again after the
/// friction rows ends each pass with the patch's rotation held, and the pile sleeps in about
/// 1.4 s. The tilt rows stay the last rows of the pass: ending on the normal rows lets
/// columns of 20 and 30 cubes fall. A patch that slides at every point carries kinetic
/// friction of a fixed size and skips the second visit, whose normal rows would raise the
/// load after the friction was limited by the lower one (the 30-degree ramp's box, mu 0.3,
/// then slid at 2.456 m/s^2 instead of 2.442; Coulomb's answer is 2.356).
pub fn solve_contact(
    c: &mut ContactConstraint,
    a: &mut BodyState,
    b: &mut BodyState,
    ctx: &PassContext,
) {
    let patch = c.patch_radius > 0.0;
    solve_normal_rows(c, a, b, ctx);
    if patch {
        solve_tilt(c, a, b);
    }
    // A biased pass of FrictionPasses::RelaxOnly: the relax passes solve the rest.
    if !ctx.friction {
        return;
    }
    // Zero friction means one row per point: skip the tangent rows entirely, and with them
    // the second visit, which only restores what they disturbed. The same test as prepare's
    // (`friction > 0` builds the rows) and the lanes' mask.
    if c.friction <= 0.0 {
        return;
    }
    let all_slide = solve_friction_rows(c, a, b);
    if patch && !all_slide {
        solve_normal_rows(c, a, b, ctx);
        solve_tilt(c, a, b);
    }
}

/// Restitution after the substeps: points that approached faster than `threshold` and
/// pushed during the step get a normal velocity of `-restitution * approach speed`.
pub fn restitution_contact(
    c: &mut ContactConstraint,
    a: &mut BodyState,
    b: &mut BodyState,
    threshold: Real,
) {
    if c.restitution == 0.0 {
        return;
    }
    let normal = c.normal;
    for i in 0..c.point_count as usize {
        let cp = c.points[i];
        // A point that never pushed is a speculative point that did not collide.
        if cp.relative_velocity > -threshold || cp.total_normal_impulse == 0.0 {
            continue;
        }
        let vn = row_velocity(a, b, &normal, &cp.normal_row);
        let delta = -cp.normal_mass * (vn + c.restitution * cp.relative_velocity);
        let accumulated = max_of(cp.normal_impulse + delta, 0.0);
        let applied = accumulated - cp.normal_impulse;
        c.points[i].normal_impulse = accumulated;
        c.points[i].total_normal_impulse += applied;
        apply_row(c, a, b, &normal, &cp.normal_row, applied);
    }
}
