//! Constraints prepared straight into a lane block: the per-manifold terms lane by lane
//! ([`ManifoldTerms`], as for a scalar constraint), then each point's rows for all lanes at
//! once, operation for operation as [`crate::prepare_contact`] builds them, so a lane holds the
//! bits a scalar constraint would hand to [`LaneBlock::set`].
//!
//! The scalar path built a whole [`crate::ContactConstraint`] per lane (about a kilobyte, with
//! rows and tilt pushes the lane kernels rebuild from the anchors) and copied it into the
//! block; here nothing goes through memory in between, and the rows of the eight lanes take
//! one vector instruction per operation.

use tumble_geometry::{MAX_MANIFOLD_POINTS, Real};

use super::LANES;
use super::block::LaneBlock;
use super::wide::{F, M, M3, V3};
use crate::constraint::ManifoldTerms;
use crate::sweep::Isa;
use crate::{Body, BodyState, Contact, Mat3, PrepareContext};

/// What preparing a constraint reads: the step's bodies, their world inverse inertias and
/// states, the contacts, the step's values, and whether friction is on (the `friction`
/// effect; off, every coefficient and carried friction impulse is zero).
#[derive(Clone, Copy)]
pub(crate) struct PrepareSource<'a> {
    pub(crate) bodies: &'a [Body],
    pub(crate) inverse_inertia: &'a [Mat3],
    pub(crate) states: &'a [BodyState],
    pub(crate) contacts: &'a [Contact],
    pub(crate) ctx: &'a PrepareContext,
    pub(crate) friction: bool,
}

/// The per-lane inputs of the point rows, gathered before the lanes are computed.
#[derive(Default)]
struct Gathered {
    centre_a: V3,
    centre_b: V3,
    a_linear: V3,
    a_angular: V3,
    b_linear: V3,
    b_angular: V3,
    inverse_inertia_a: M3,
    inverse_inertia_b: M3,
    /// Lanes whose mixed friction is positive (their friction rows are built).
    frictional: M,
    position: [V3; MAX_MANIFOLD_POINTS],
    depth: [F; MAX_MANIFOLD_POINTS],
    warm_normal: [F; MAX_MANIFOLD_POINTS],
    warm_friction: [V3; MAX_MANIFOLD_POINTS],
}

/// `row_mass` of constraint.rs per lane: `1 / (J M^-1 J^T)` of direction `d` at anchors
/// `anchor_a`, `anchor_b`, or 0 where both bodies are immovable along it.
#[inline(always)]
fn row_mass(b: &LaneBlock, g: &Gathered, anchor_a: &V3, anchor_b: &V3, d: &V3) -> F {
    let arm_a = anchor_a.cross(d);
    let arm_b = anchor_b.cross(d);
    let push_a = g.inverse_inertia_a.mul(&arm_a);
    let push_b = g.inverse_inertia_b.mul(&arm_b);
    let d2 = d.cmul(d);
    let k = b.inverse_mass_a.dot(&d2)
        + b.inverse_mass_b.dot(&d2)
        + (arm_a.dot(&push_a) + arm_b.dot(&push_b));
    let zero = F::splat(0.0);
    k.gt(zero).select(F::splat(1.0) / k, zero)
}

/// Asks the cache for every line of `item`: a hint that changes no result, only when the
/// lines arrive (nothing off x86-64).
#[inline(always)]
pub(crate) fn prefetch<T>(item: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let start = (item as *const T).cast::<i8>();
        let mut offset = 0;
        while offset < std::mem::size_of::<T>() {
            // SAFETY: a prefetch reads nothing and cannot fault; the address lies within
            // `item`.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(start.wrapping_add(offset)) };
            offset += 64;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = item;
}

/// Asks the cache for what preparing the block of contacts `indices` will read first: the
/// contacts themselves, or, with `bodies`, their bodies, inverse inertias and states (which
/// reads the contacts' body indices, so it should follow a prefetch of the contacts by a
/// block or more).
#[inline(always)]
pub(crate) fn prefetch_block(indices: &[u32], src: &PrepareSource<'_>, bodies: bool) {
    for &i in indices {
        let Some(contact) = src.contacts.get(i as usize) else {
            continue;
        };
        if !bodies {
            prefetch(contact);
            continue;
        }
        for b in [contact.body_a as usize, contact.body_b as usize] {
            if let (Some(body), Some(j), Some(s)) = (
                src.bodies.get(b),
                src.inverse_inertia.get(b),
                src.states.get(b),
            ) {
                prefetch(body);
                prefetch(j);
                prefetch(s);
            }
        }
    }
}

impl LaneBlock {
    /// The block filled with the constraints of `indices` (1 to [`LANES`] contacts), as
    /// [`LaneBlock::start`] and [`LaneBlock::set`] of each prepared constraint fill it, with
    /// the lanes' rows computed on `isa`.
    pub(crate) fn prepare(&mut self, indices: &[u32], src: &PrepareSource<'_>, isa: Isa) {
        match isa {
            // SAFETY: AVX2 is present (checked here, as the sweeps check it).
            Isa::Avx2 if crate::sweep::avx2_present() => unsafe { self.prepare_avx2(indices, src) },
            Isa::Avx2 | Isa::Portable => self.prepare_lanes(indices, src),
        }
    }

    /// [`LaneBlock::prepare_lanes`] compiled for AVX2: the same operations on 256-bit
    /// registers.
    ///
    /// # Safety
    /// The processor has AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn prepare_avx2(&mut self, indices: &[u32], src: &PrepareSource<'_>) {
        self.prepare_lanes(indices, src);
    }

    /// No AVX2 off x86-64.
    ///
    /// # Safety
    /// None needed; as the x86-64 version.
    #[cfg(not(target_arch = "x86_64"))]
    unsafe fn prepare_avx2(&mut self, indices: &[u32], src: &PrepareSource<'_>) {
        self.prepare_lanes(indices, src);
    }

    #[inline(always)]
    fn prepare_lanes(&mut self, indices: &[u32], src: &PrepareSource<'_>) {
        self.start(indices.len());
        let mut g = Gathered::default();
        for (l, &index) in indices.iter().enumerate() {
            self.gather_lane(l, index as usize, src, &mut g);
        }
        let scale = F::splat(src.ctx.warm_start_scale);
        let zero = F::splat(0.0);
        let n = self.normal;
        let tangents = [self.tangent1, self.tangent2];
        let frictional = g.frictional;
        for i in 0..self.max_points as usize {
            let anchor_a = g.position[i] - g.centre_a;
            let anchor_b = g.position[i] - g.centre_b;
            let dv = g.b_linear + g.b_angular.cross(&anchor_b)
                - g.a_linear
                - g.a_angular.cross(&anchor_a);
            let normal_mass = row_mass(self, &g, &anchor_a, &anchor_b, &n);
            let tangent_mass = if frictional.any() {
                tangents
                    .map(|t| frictional.select(row_mass(self, &g, &anchor_a, &anchor_b, &t), zero))
            } else {
                [zero; 2]
            };
            let tangent_impulse = if src.friction {
                tangents.map(|t| frictional.select(scale * g.warm_friction[i].dot(&t), zero))
            } else {
                [zero; 2]
            };
            let p = &mut self.points[i];
            p.anchor_a = anchor_a;
            p.anchor_b = anchor_b;
            p.base_separation = -g.depth[i] - (anchor_b - anchor_a).dot(&n);
            p.normal_mass = normal_mass;
            p.tangent_mass = tangent_mass;
            p.normal_impulse = scale * g.warm_normal[i];
            p.tangent_impulse = tangent_impulse;
            p.total_normal_impulse = zero;
            p.relative_velocity = dv.dot(&n);
        }
    }

    /// Lane `l` set to the per-manifold terms of contact `index`, and its point and body
    /// inputs gathered into `g` (the lanes past the block's length keep zeros, and lane 0's
    /// bodies, as [`LaneBlock::set`] leaves them).
    #[inline(always)]
    fn gather_lane(&mut self, l: usize, index: usize, src: &PrepareSource<'_>, g: &mut Gathered) {
        let contact = &src.contacts[index];
        let (ia, ib) = (contact.body_a as usize, contact.body_b as usize);
        let (a, b) = (&src.bodies[ia], &src.bodies[ib]);
        let (ja, jb) = (&src.inverse_inertia[ia], &src.inverse_inertia[ib]);
        let m = ManifoldTerms::new(a, b, ja, jb, contact, src.ctx);
        if l == 0 {
            self.body_a = [contact.body_a; LANES];
            self.body_b = [contact.body_b; LANES];
        }
        self.max_points = self.max_points.max(m.point_count);
        self.contact[l] = index as u32;
        self.body_a[l] = contact.body_a;
        self.body_b[l] = contact.body_b;
        self.dynamic_a[l] = m.dynamic_a;
        self.dynamic_b[l] = m.dynamic_b;
        self.normal.set(l, &m.normal);
        self.tangent1.set(l, &m.tangent1);
        self.tangent2.set(l, &m.tangent2);
        self.inverse_mass_a.set(l, &m.inverse_mass_a);
        self.inverse_mass_b.set(l, &m.inverse_mass_b);
        // The friction effect off: no friction rows and no carried friction impulse, as the
        // solve stage does to a scalar constraint.
        self.friction.0[l] = if src.friction { m.friction } else { 0.0 };
        self.restitution.0[l] = m.restitution;
        self.bias_rate.0[l] = m.softness.bias_rate;
        self.mass_scale.0[l] = m.softness.mass_scale;
        self.impulse_scale.0[l] = m.softness.impulse_scale;
        self.slop.0[l] = m.slop;
        self.point_count.0[l] = m.point_count as Real;
        self.patch.0[l] = if m.patch_radius > 0.0 { !0 } else { 0 };
        self.patch_radius.0[l] = m.patch_radius;
        for k in 0..2 {
            self.tilt_mass[k].0[l] = m.tilt_mass[k];
            self.tilt_impulse[k].0[l] = m.tilt_impulse[k];
        }
        let count = m.point_count as usize;
        for (i, mask) in self.point_mask.iter_mut().enumerate() {
            mask.0[l] = if i < count { !0 } else { 0 };
        }
        g.frictional.0[l] = if m.friction > 0.0 { !0 } else { 0 };
        g.centre_a.set(l, &a.pose.translation.vector);
        g.centre_b.set(l, &b.pose.translation.vector);
        let (sa, sb) = (&src.states[ia], &src.states[ib]);
        g.a_linear.set(l, &sa.linear_velocity);
        g.a_angular.set(l, &sa.angular_velocity);
        g.b_linear.set(l, &sb.linear_velocity);
        g.b_angular.set(l, &sb.angular_velocity);
        g.inverse_inertia_a.set(l, ja);
        g.inverse_inertia_b.set(l, jb);
        for (i, p) in contact.manifold.points().iter().enumerate() {
            g.position[i].set(l, &p.position.coords);
            g.depth[i].0[l] = p.depth;
            g.warm_normal[i].0[l] = contact.impulses[i].normal;
            g.warm_friction[i].set(l, &contact.impulses[i].friction);
        }
    }
}
