//! The contact kernels on [`LANES`] constraints at once: the constraints of one graph color
//! packed into blocks whose every field holds one value per lane (structure of arrays), so the
//! compiler turns each arithmetic step into one vector instruction.
//!
//! Each lane does exactly what [`crate::contact_solver`] does for one constraint, operation for
//! operation and in the same order (the dot product `(x x' + y y') + z z'` as nalgebra forms
//! it, a quaternion turning a vector as nalgebra does, the clamps as a compare and a select,
//! as the scalar kernel's `max_of` and `min_of` do), and a branch of the scalar code becomes a
//! mask that selects, lane by lane, the new value or the old one. Skipped work is never computed as "add zero": adding `0.0` to `-0.0`
//! changes a bit. So a lane ends with the bits the scalar kernel gives, and the solve's result
//! does not depend on the kernel width (the tests compare the two bit for bit).
//!
//! A color's constraints share no dynamic body, which is what lets them run side by side:
//! every lane reads its bodies' velocities at the start of the block, none reads a body that
//! another lane writes, and each dynamic body is written back by one lane only.

use std::array::from_fn;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use tumble_geometry::{MAX_MANIFOLD_POINTS, Real, Vec3};

use crate::Mat3;

use crate::{BodyState, Contact, ContactConstraint, PassContext};

/// Constraints per block: 8 lanes of `f32` fill one 256-bit AVX register (x86-64 processors
/// with AVX2 run the kernels so, detected at run time); elsewhere each step takes two 128-bit
/// instructions, which every x86-64 and aarch64 processor has.
pub const LANES: usize = 8;

/// One `f32` per lane.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub(crate) struct F(pub [Real; LANES]);

/// A lane mask: all ones (true) or all zeros (false) per lane, as vector compares give.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(C, align(32))]
pub(crate) struct M(pub [u32; LANES]);

macro_rules! lane_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for F {
            type Output = F;
            #[inline(always)]
            fn $method(self, o: F) -> F {
                F(from_fn(|i| self.0[i] $op o.0[i]))
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

impl Neg for F {
    type Output = F;
    #[inline(always)]
    fn neg(self) -> F {
        F(self.0.map(|x| -x))
    }
}

impl F {
    /// The same value in every lane.
    #[inline(always)]
    pub(crate) fn splat(v: Real) -> F {
        F([v; LANES])
    }

    /// `contact_solver::max_of` lane by lane: `self > o ? self : o`.
    #[inline(always)]
    fn max(self, o: F) -> F {
        self.gt(o).select(self, o)
    }

    /// `contact_solver::min_of` lane by lane: `self < o ? self : o`.
    #[inline(always)]
    fn min(self, o: F) -> F {
        o.gt(self).select(self, o)
    }

    #[inline(always)]
    fn sqrt(self) -> F {
        F(from_fn(|i| self.0[i].sqrt()))
    }

    /// `self > o` lane by lane.
    #[inline(always)]
    fn gt(self, o: F) -> M {
        M(from_fn(|i| if self.0[i] > o.0[i] { !0 } else { 0 }))
    }

    /// `self == o` lane by lane.
    #[inline(always)]
    fn eq(self, o: F) -> M {
        M(from_fn(|i| if self.0[i] == o.0[i] { !0 } else { 0 }))
    }
}

impl M {
    pub(crate) const ALL: M = M([!0; LANES]);

    /// True when any lane is set.
    #[inline(always)]
    fn any(self) -> bool {
        self.0.iter().fold(0, |acc, &m| acc | m) != 0
    }

    /// `a` where the mask is set, `b` elsewhere, bit for bit.
    #[inline(always)]
    fn select(self, a: F, b: F) -> F {
        F(from_fn(|i| {
            Real::from_bits((a.0[i].to_bits() & self.0[i]) | (b.0[i].to_bits() & !self.0[i]))
        }))
    }

    #[inline(always)]
    fn select3(self, a: V3, b: V3) -> V3 {
        V3 {
            x: self.select(a.x, b.x),
            y: self.select(a.y, b.y),
            z: self.select(a.z, b.z),
        }
    }
}

impl BitAnd for M {
    type Output = M;
    #[inline(always)]
    fn bitand(self, o: M) -> M {
        M(from_fn(|i| self.0[i] & o.0[i]))
    }
}

impl BitOr for M {
    type Output = M;
    #[inline(always)]
    fn bitor(self, o: M) -> M {
        M(from_fn(|i| self.0[i] | o.0[i]))
    }
}

impl Not for M {
    type Output = M;
    #[inline(always)]
    fn not(self) -> M {
        M(from_fn(|i| !self.0[i]))
    }
}

/// A vector per lane.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct V3 {
    x: F,
    y: F,
    z: F,
}

impl V3 {
    /// Lane `l` set to `v`.
    #[inline(always)]
    fn set(&mut self, l: usize, v: &Vec3) {
        self.x.0[l] = v.x;
        self.y.0[l] = v.y;
        self.z.0[l] = v.z;
    }

    /// Lane `l` as a vector.
    #[inline(always)]
    pub(crate) fn get(&self, l: usize) -> Vec3 {
        Vec3::new(self.x.0[l], self.y.0[l], self.z.0[l])
    }

    /// nalgebra's `dot` of 3-vectors: `(x x' + y y') + z z'`.
    #[inline(always)]
    fn dot(&self, o: &V3) -> F {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// nalgebra's `cross`.
    #[inline(always)]
    fn cross(&self, b: &V3) -> V3 {
        V3 {
            x: self.y * b.z - self.z * b.y,
            y: self.z * b.x - self.x * b.z,
            z: self.x * b.y - self.y * b.x,
        }
    }

    /// `component_mul`.
    #[inline(always)]
    fn cmul(&self, o: &V3) -> V3 {
        V3 {
            x: self.x * o.x,
            y: self.y * o.y,
            z: self.z * o.z,
        }
    }

    /// Vector times a scalar per lane.
    #[inline(always)]
    fn scale(&self, s: F) -> V3 {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

impl Add for V3 {
    type Output = V3;
    #[inline(always)]
    fn add(self, o: V3) -> V3 {
        V3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl Sub for V3 {
    type Output = V3;
    #[inline(always)]
    fn sub(self, o: V3) -> V3 {
        V3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

/// A unit quaternion per lane: vector part and scalar part.
#[derive(Clone, Copy, Debug, Default)]
struct Q {
    v: V3,
    w: F,
}

impl Q {
    /// nalgebra's `UnitQuaternion * Vector3`: `t = 2 (q_v x v)`, then `(t w + q_v x t) + v`.
    #[inline(always)]
    fn rotate(&self, v: &V3) -> V3 {
        let t = self.v.cross(v).scale(F::splat(2.0));
        let cross = self.v.cross(&t);
        t.scale(self.w) + cross + *v
    }
}

/// A 3 x 3 matrix per lane, row by row.
#[derive(Clone, Copy, Debug, Default)]
struct M3([V3; 3]);

impl M3 {
    /// Lane `l` set to `m`.
    #[inline(always)]
    fn set(&mut self, l: usize, m: &Mat3) {
        for (i, row) in self.0.iter_mut().enumerate() {
            row.set(l, &Vec3::new(m[(i, 0)], m[(i, 1)], m[(i, 2)]));
        }
    }

    /// nalgebra's `Matrix3 * Vector3`: row `i` is `(m_i0 x + m_i1 y) + m_i2 z`.
    #[inline(always)]
    fn mul(&self, v: &V3) -> V3 {
        let row = |r: &V3| r.x * v.x + r.y * v.y + r.z * v.z;
        V3 {
            x: row(&self.0[0]),
            y: row(&self.0[1]),
            z: row(&self.0[2]),
        }
    }
}

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
    fn new(c: &LaneBlock, p: &Point, d: &V3) -> Row {
        let arm_a = p.anchor_a.cross(d);
        let arm_b = p.anchor_b.cross(d);
        Row {
            arm_a,
            arm_b,
            push_a: c.inverse_inertia_a.mul(&arm_a),
            push_b: c.inverse_inertia_b.mul(&arm_b),
        }
    }
}

/// [`crate::ConstraintPoint`] per lane, without what the passes never read.
#[derive(Clone, Copy, Debug, Default)]
struct Point {
    anchor_a: V3,
    anchor_b: V3,
    base_separation: F,
    normal_mass: F,
    tangent_mass: [F; 2],
    normal_impulse: F,
    tangent_impulse: [F; 2],
    total_normal_impulse: F,
    relative_velocity: F,
}

/// Up to [`LANES`] constraints of one color, field by field.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LaneBlock {
    /// Constraints in the block (the lanes past it are padding, never written back).
    len: u32,
    /// Each lane's contact (index into the step's contacts).
    contact: [u32; LANES],
    /// Most points of any lane.
    max_points: u32,
    body_a: [u32; LANES],
    body_b: [u32; LANES],
    dynamic_a: [bool; LANES],
    dynamic_b: [bool; LANES],
    normal: V3,
    tangent1: V3,
    tangent2: V3,
    inverse_mass_a: V3,
    inverse_mass_b: V3,
    friction: F,
    restitution: F,
    bias_rate: F,
    mass_scale: F,
    impulse_scale: F,
    slop: F,
    /// `point_count` as a float (the tilt limit's factor).
    point_count: F,
    /// Per point, the lanes that have it.
    point_mask: [M; MAX_MANIFOLD_POINTS],
    /// Lanes with a face patch (`patch_radius > 0`).
    patch: M,
    patch_radius: F,
    tilt_mass: [F; 2],
    tilt_impulse: [F; 2],
    inverse_inertia_a: M3,
    inverse_inertia_b: M3,
    points: [Point; MAX_MANIFOLD_POINTS],
}

impl LaneBlock {
    /// Starts a block of `len` constraints (1 to [`LANES`]) whose lanes [`LaneBlock::set`]
    /// fills next. A block with padding lanes is cleared first, so that they hold zeros; a
    /// full block keeps last step's values in the points past each lane's count, which the
    /// point masks leave out of every result.
    #[inline]
    pub(crate) fn start(&mut self, len: usize) {
        debug_assert!(len > 0 && len <= LANES);
        if len < LANES {
            *self = LaneBlock::default();
        }
        self.len = len as u32;
        self.max_points = 0;
    }

    /// Lane `l` set to constraint `c`. Lane 0's bodies are also every padding lane's (any
    /// index in range would do: padding lanes are computed and thrown away).
    #[inline]
    pub(crate) fn set(&mut self, l: usize, c: &ContactConstraint) {
        let b = self;
        if l == 0 {
            b.body_a = [c.body_a; LANES];
            b.body_b = [c.body_b; LANES];
        }
        b.max_points = b.max_points.max(c.point_count);
        b.contact[l] = c.contact;
        b.body_a[l] = c.body_a;
        b.body_b[l] = c.body_b;
        b.dynamic_a[l] = c.dynamic_a;
        b.dynamic_b[l] = c.dynamic_b;
        b.normal.set(l, &c.normal);
        b.tangent1.set(l, &c.tangent1);
        b.tangent2.set(l, &c.tangent2);
        b.inverse_mass_a.set(l, &c.inverse_mass_a);
        b.inverse_mass_b.set(l, &c.inverse_mass_b);
        b.inverse_inertia_a.set(l, &c.inverse_inertia_a);
        b.inverse_inertia_b.set(l, &c.inverse_inertia_b);
        b.friction.0[l] = c.friction;
        b.restitution.0[l] = c.restitution;
        b.bias_rate.0[l] = c.softness.bias_rate;
        b.mass_scale.0[l] = c.softness.mass_scale;
        b.impulse_scale.0[l] = c.softness.impulse_scale;
        b.slop.0[l] = c.slop;
        b.point_count.0[l] = c.point_count as Real;
        b.patch.0[l] = if c.patch_radius > 0.0 { !0 } else { 0 };
        b.patch_radius.0[l] = c.patch_radius;
        for k in 0..2 {
            b.tilt_mass[k].0[l] = c.tilt_mass[k];
            b.tilt_impulse[k].0[l] = c.tilt_impulse[k];
        }
        for (i, q) in b.points.iter_mut().enumerate() {
            let has = i < c.point_count as usize;
            b.point_mask[i].0[l] = if has { !0 } else { 0 };
            if !has {
                continue;
            }
            let p = &c.points[i];
            q.anchor_a.set(l, &p.anchor_a);
            q.anchor_b.set(l, &p.anchor_b);
            q.base_separation.0[l] = p.base_separation;
            q.normal_mass.0[l] = p.normal_mass;
            q.normal_impulse.0[l] = p.normal_impulse;
            q.total_normal_impulse.0[l] = p.total_normal_impulse;
            q.relative_velocity.0[l] = p.relative_velocity;
            for k in 0..2 {
                q.tangent_mass[k].0[l] = p.tangent_mass[k];
                q.tangent_impulse[k].0[l] = p.tangent_impulse[k];
            }
        }
    }

    /// True when some lane has restitution.
    pub(crate) fn has_restitution(&self) -> bool {
        self.restitution.0[..self.len as usize]
            .iter()
            .any(|&r| r > 0.0)
    }

    /// Writes each lane's impulses into its contact, as
    /// [`ContactConstraint::store_impulses`] does.
    pub(crate) fn store(&self, contacts: &mut [Contact]) {
        for l in 0..self.len as usize {
            let (t1, t2) = (self.tangent1.get(l), self.tangent2.get(l));
            let contact = &mut contacts[self.contact[l] as usize];
            for (i, p) in self.points.iter().enumerate() {
                if self.point_mask[i].0[l] == 0 {
                    continue;
                }
                contact.impulses[i].normal = p.normal_impulse.0[l];
                contact.impulses[i].friction =
                    t1 * p.tangent_impulse[0].0[l] + t2 * p.tangent_impulse[1].0[l];
                contact.total_normal_impulse[i] = p.total_normal_impulse.0[l];
            }
            contact.tilt_impulse = t1 * self.tilt_impulse[0].0[l] + t2 * self.tilt_impulse[1].0[l];
        }
    }

    /// The lanes' bodies read from the `len` states at `states`.
    ///
    /// # Panics
    /// When a body index is out of range (a caller's broken constraint, as in the scalar
    /// sweep).
    ///
    /// # Safety
    /// `states` points at `len` states that no other thread writes meanwhile.
    #[inline(always)]
    pub(crate) unsafe fn gather(&self, states: *const BodyState, len: usize) -> LaneBodies {
        let mut v = LaneBodies {
            inverse_mass_a: self.inverse_mass_a,
            inverse_mass_b: self.inverse_mass_b,
            ..LaneBodies::default()
        };
        for l in 0..LANES {
            let (ia, ib) = (self.body_a[l] as usize, self.body_b[l] as usize);
            assert!(ia < len && ib < len, "body index out of range");
            // SAFETY: in range (checked); the caller's contract.
            let (a, b) = unsafe { (&*states.add(ia), &*states.add(ib)) };
            v.a_linear.set(l, &a.linear_velocity);
            v.a_angular.set(l, &a.angular_velocity);
            v.b_linear.set(l, &b.linear_velocity);
            v.b_angular.set(l, &b.angular_velocity);
            v.delta_position
                .set(l, &(b.delta_position - a.delta_position));
            let (qa, qb) = (a.delta_rotation.as_ref(), b.delta_rotation.as_ref());
            v.rotation_a.v.set(l, &qa.imag());
            v.rotation_a.w.0[l] = qa.w;
            v.rotation_b.v.set(l, &qb.imag());
            v.rotation_b.w.0[l] = qb.w;
        }
        v
    }

    /// Writes the solved velocities of the block's dynamic bodies into `states`.
    ///
    /// # Safety
    /// `states` points at `len` states; every body index of the block is below `len`
    /// (checked by [`LaneBlock::gather`] on the same states, and no kernel changes a block's
    /// body indices or dynamic flags: they are written by [`LaneBlock::set`] only), and no
    /// other thread reads or writes this block's dynamic bodies meanwhile.
    #[inline(always)]
    pub(crate) unsafe fn scatter(&self, v: &LaneBodies, states: *mut BodyState) {
        for l in 0..self.len as usize {
            // SAFETY: the caller's contract.
            unsafe {
                if self.dynamic_a[l] {
                    let s = &mut *states.add(self.body_a[l] as usize);
                    s.linear_velocity = v.a_linear.get(l);
                    s.angular_velocity = v.a_angular.get(l);
                }
                if self.dynamic_b[l] {
                    let s = &mut *states.add(self.body_b[l] as usize);
                    s.linear_velocity = v.b_linear.get(l);
                    s.angular_velocity = v.b_angular.get(l);
                }
            }
        }
    }
}

/// The two bodies of each lane: velocities (which the passes change), inverse masses, and
/// the step's deltas (which they read to rebuild the separation).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LaneBodies {
    a_linear: V3,
    a_angular: V3,
    b_linear: V3,
    b_angular: V3,
    inverse_mass_a: V3,
    inverse_mass_b: V3,
    /// `delta_position_b - delta_position_a`.
    delta_position: V3,
    rotation_a: Q,
    rotation_b: Q,
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

/// [`crate::warm_start_contact`] on every lane.
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
        apply_row(v, &normal, &Row::new(c, &p, &normal), p.normal_impulse, m);
        let mf = m & friction;
        if mf.any() {
            apply_row(v, &t1, &Row::new(c, &p, &t1), p.tangent_impulse[0], mf);
            apply_row(v, &t2, &Row::new(c, &p, &t2), p.tangent_impulse[1], mf);
        }
    }
    let (push_a, push_b) = tilt_push(c);
    apply_tilt(v, &push_a, &push_b, c.tilt_impulse, M::ALL);
}

/// `I_a^-1 t_k` and `I_b^-1 t_k` of the two tangents, as `prepare_contact` computes them.
#[inline(always)]
fn tilt_push(c: &LaneBlock) -> ([V3; 2], [V3; 2]) {
    let t = [c.tangent1, c.tangent2];
    (
        t.map(|t| c.inverse_inertia_a.mul(&t)),
        t.map(|t| c.inverse_inertia_b.mul(&t)),
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
        let row = Row::new(c, &c.points[i], &normal);
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
    let (push_a, push_b) = tilt_push(c);
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
            Row::new(c, &c.points[i], &t1),
            Row::new(c, &c.points[i], &t2),
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
        let row = Row::new(c, &c.points[i], &normal);
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
