//! A block of up to [`LANES`] constraints of one color, field by field: filled from the
//! prepared constraints, its bodies gathered from and scattered back into the state array,
//! its impulses stored into the contacts.

use tumble_geometry::MAX_MANIFOLD_POINTS;

use super::LANES;
use super::wide::{F, M, M3, Q, V3};
use crate::{BodyState, Contact, Mat3};

#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Point {
    pub(super) anchor_a: V3,
    pub(super) anchor_b: V3,
    pub(super) base_separation: F,
    pub(super) normal_mass: F,
    pub(super) tangent_mass: [F; 2],
    pub(super) normal_impulse: F,
    pub(super) tangent_impulse: [F; 2],
    pub(super) total_normal_impulse: F,
    pub(super) relative_velocity: F,
}

/// Up to [`LANES`] constraints of one color, field by field.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LaneBlock {
    /// Constraints in the block (the lanes past it are padding, never written back).
    pub(super) len: u32,
    /// Each lane's contact (index into the step's contacts).
    pub(super) contact: [u32; LANES],
    /// Most points of any lane.
    pub(super) max_points: u32,
    pub(super) body_a: [u32; LANES],
    pub(super) body_b: [u32; LANES],
    pub(super) dynamic_a: [bool; LANES],
    pub(super) dynamic_b: [bool; LANES],
    pub(super) normal: V3,
    pub(super) tangent1: V3,
    pub(super) tangent2: V3,
    pub(super) inverse_mass_a: V3,
    pub(super) inverse_mass_b: V3,
    pub(super) friction: F,
    pub(super) restitution: F,
    pub(super) bias_rate: F,
    pub(super) mass_scale: F,
    pub(super) impulse_scale: F,
    pub(super) slop: F,
    /// `point_count` as a float (the tilt limit's factor).
    pub(super) point_count: F,
    /// Per point, the lanes that have it.
    pub(super) point_mask: [M; MAX_MANIFOLD_POINTS],
    /// Lanes with a face patch (`patch_radius > 0`).
    pub(super) patch: M,
    pub(super) patch_radius: F,
    pub(super) tilt_mass: [F; 2],
    pub(super) tilt_impulse: [F; 2],
    pub(super) points: [Point; MAX_MANIFOLD_POINTS],
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
    ///
    /// The solve fills its blocks with [`LaneBlock::prepare`]; this is the reference the
    /// tests hold it to, and how they build blocks from random constraints.
    #[cfg(test)]
    pub(crate) fn set(&mut self, l: usize, c: &crate::ContactConstraint) {
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
        b.friction.0[l] = c.friction;
        b.restitution.0[l] = c.restitution;
        b.bias_rate.0[l] = c.softness.bias_rate;
        b.mass_scale.0[l] = c.softness.mass_scale;
        b.impulse_scale.0[l] = c.softness.impulse_scale;
        b.slop.0[l] = c.slop;
        b.point_count.0[l] = c.point_count as tumble_geometry::Real;
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

    /// The bits of everything the kernels read of lane `l`: its per-constraint fields, its
    /// point masks and the points it has (the points past its count are masked out of every
    /// result, whatever they hold), and the block's length, point bound and body indices.
    #[cfg(test)]
    pub(crate) fn lane_bits(&self, l: usize) -> Vec<u32> {
        let f = |x: &F| x.0[l].to_bits();
        let v = |x: &V3| [f(&x.x), f(&x.y), f(&x.z)];
        let mut bits = vec![
            self.len,
            self.max_points,
            self.contact[l],
            u32::from(self.dynamic_a[l]),
            u32::from(self.dynamic_b[l]),
            self.patch.0[l],
        ];
        bits.extend(self.body_a.iter().chain(&self.body_b));
        for x in [
            &self.normal,
            &self.tangent1,
            &self.tangent2,
            &self.inverse_mass_a,
            &self.inverse_mass_b,
        ] {
            bits.extend(v(x));
        }
        for x in [
            &self.friction,
            &self.restitution,
            &self.bias_rate,
            &self.mass_scale,
            &self.impulse_scale,
            &self.slop,
            &self.point_count,
            &self.patch_radius,
            &self.tilt_mass[0],
            &self.tilt_mass[1],
            &self.tilt_impulse[0],
            &self.tilt_impulse[1],
        ] {
            bits.push(f(x));
        }
        for (mask, p) in self.point_mask.iter().zip(&self.points) {
            bits.push(mask.0[l]);
            if mask.0[l] == 0 {
                continue;
            }
            bits.extend(v(&p.anchor_a));
            bits.extend(v(&p.anchor_b));
            for x in [
                &p.base_separation,
                &p.normal_mass,
                &p.tangent_mass[0],
                &p.tangent_mass[1],
                &p.normal_impulse,
                &p.tangent_impulse[0],
                &p.tangent_impulse[1],
                &p.total_normal_impulse,
                &p.relative_velocity,
            ] {
                bits.push(f(x));
            }
        }
        bits
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
            self.store_lane(l, &mut contacts[self.contact[l] as usize]);
        }
    }

    /// Lane `l`'s impulses written into its contact (`contact`, the lane's
    /// [`LaneBlock::contact_of`]).
    #[inline]
    pub(crate) fn store_lane(&self, l: usize, contact: &mut Contact) {
        let (t1, t2) = (self.tangent1.get(l), self.tangent2.get(l));
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

    /// The constraints in the block (lanes `0..len`).
    #[inline]
    pub(crate) fn len(&self) -> usize {
        self.len as usize
    }

    /// The contact (index into the step's contacts) of lane `l`.
    #[inline]
    pub(crate) fn contact_of(&self, l: usize) -> usize {
        self.contact[l] as usize
    }

    /// The lanes' bodies read from the `len` states at `states`.
    ///
    /// # Panics
    /// When a body index is out of range (a caller's broken constraint, as in the scalar
    /// sweep).
    ///
    /// # Safety
    /// `states` points at `len` states that no other thread writes meanwhile, and
    /// `inverse_inertia` at the `len` bodies' world inverse inertias of the step (the ones
    /// `prepare_contact` built the constraints with).
    #[inline(always)]
    pub(crate) unsafe fn gather(
        &self,
        states: *const BodyState,
        inverse_inertia: *const Mat3,
        len: usize,
    ) -> LaneBodies {
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
            // SAFETY: in range (checked); the caller's contract.
            let (ja, jb) = unsafe { (&*inverse_inertia.add(ia), &*inverse_inertia.add(ib)) };
            v.inverse_inertia_a.set(l, ja);
            v.inverse_inertia_b.set(l, jb);
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

    /// [`LaneBlock::gather`] with AVX2: each lane's state and inverse inertia loaded as rows
    /// of eight floats and transposed into lanes by shuffles, eight lanes at a time, instead of
    /// one float at a time. The same values, bit for bit (a load and a shuffle move bits; the
    /// one subtraction is the scalar gather's, lane by lane).
    ///
    /// # Panics
    /// As [`LaneBlock::gather`].
    ///
    /// # Safety
    /// As [`LaneBlock::gather`], and the processor has AVX2.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(crate) unsafe fn gather_avx2(
        &self,
        states: *const BodyState,
        inverse_inertia: *const Mat3,
        len: usize,
    ) -> LaneBodies {
        // A state is thirteen floats: linear velocity, angular velocity, delta position and
        // the delta rotation's (i, j, k, w); an inverse inertia nine, column by column.
        const _: () = {
            assert!(std::mem::size_of::<BodyState>() == 52);
            assert!(std::mem::offset_of!(BodyState, linear_velocity) == 0);
            assert!(std::mem::offset_of!(BodyState, angular_velocity) == 12);
            assert!(std::mem::offset_of!(BodyState, delta_position) == 24);
            assert!(std::mem::offset_of!(BodyState, delta_rotation) == 36);
            assert!(std::mem::size_of::<Mat3>() == 36);
        };
        let mut v = LaneBodies {
            inverse_mass_a: self.inverse_mass_a,
            inverse_mass_b: self.inverse_mass_b,
            ..LaneBodies::default()
        };
        // SAFETY: the caller's contract (AVX2 present, valid arrays of `len` elements).
        let [a0, a1, ai0, ai1] = unsafe { gather_side(&self.body_a, states, inverse_inertia, len) };
        // SAFETY: as above.
        let [b0, b1, bi0, bi1] = unsafe { gather_side(&self.body_b, states, inverse_inertia, len) };
        // Row 0 of a state: linear (0, 1, 2), angular (3, 4, 5), delta position x, y (6, 7);
        // row 1 (from float 5): delta position z (3), rotation i, j, k, w (4 to 7).
        let three = |t: &[F; 8], i: usize| V3 {
            x: t[i],
            y: t[i + 1],
            z: t[i + 2],
        };
        let delta = |r0: &[F; 8], r1: &[F; 8]| V3 {
            x: r0[6],
            y: r0[7],
            z: r1[3],
        };
        // Column-major: floats 0..8 are m00 m10 m20 m01 m11 m21 m02 m12, and the load from
        // float 1 ends with m22; the lanes hold the matrix row by row (row `r`: floats `r`,
        // `r + 3`, `r + 6`, the last row's third from the second load: row 2's `z` read here
        // is float 7, m12, which `matrix` replaces with the second load's m22).
        let three_apart = |t: &[F; 8], r: usize| V3 {
            x: t[r],
            y: t[r + 3],
            z: t[(r + 6).min(7)],
        };
        let matrix = |i0: &[F; 8], i1: &[F; 8]| {
            M3([
                three_apart(i0, 0),
                three_apart(i0, 1),
                V3 {
                    z: i1[7],
                    ..three_apart(i0, 2)
                },
            ])
        };
        v.a_linear = three(&a0, 0);
        v.a_angular = three(&a0, 3);
        v.b_linear = three(&b0, 0);
        v.b_angular = three(&b0, 3);
        v.delta_position = delta(&b0, &b1) - delta(&a0, &a1);
        v.rotation_a = Q {
            v: three(&a1, 4),
            w: a1[7],
        };
        v.rotation_b = Q {
            v: three(&b1, 4),
            w: b1[7],
        };
        v.inverse_inertia_a = matrix(&ai0, &ai1);
        v.inverse_inertia_b = matrix(&bi0, &bi1);
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
    pub(super) a_linear: V3,
    pub(super) a_angular: V3,
    pub(super) b_linear: V3,
    pub(super) b_angular: V3,
    pub(super) inverse_mass_a: V3,
    pub(super) inverse_mass_b: V3,
    /// The bodies' world inverse inertias, gathered per body rather than stored in every
    /// block (a tenth of a block's bytes, read by every pass).
    pub(super) inverse_inertia_a: M3,
    pub(super) inverse_inertia_b: M3,
    /// `delta_position_b - delta_position_a`.
    pub(super) delta_position: V3,
    pub(super) rotation_a: Q,
    pub(super) rotation_b: Q,
}

#[cfg(all(test, target_arch = "x86_64"))]
impl LaneBodies {
    /// The bits of every field, lane by lane, for comparing two gathers.
    pub(crate) fn bits(&self) -> Vec<u32> {
        let v = |x: &V3| [x.x, x.y, x.z];
        let mut fields = vec![self.rotation_a.w, self.rotation_b.w];
        for x in [
            &self.a_linear,
            &self.a_angular,
            &self.b_linear,
            &self.b_angular,
            &self.inverse_mass_a,
            &self.inverse_mass_b,
            &self.delta_position,
            &self.rotation_a.v,
            &self.rotation_b.v,
        ]
        .into_iter()
        .chain(&self.inverse_inertia_a.0)
        .chain(&self.inverse_inertia_b.0)
        {
            fields.extend(v(x));
        }
        fields
            .iter()
            .flat_map(|f| f.0.map(|x| x.to_bits()))
            .collect()
    }
}

/// One side's bodies (`bodies`, one per lane) as four 8 x 8 tiles transposed into lanes:
/// state floats 0..8, state floats 5..13, inverse inertia floats 0..8 and 1..9.
///
/// # Safety
/// AVX2 is present (the caller is compiled with it, so that this inlines into it), and
/// `states` and `inverse_inertia` point at `len` elements each.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn gather_side(
    bodies: &[u32; LANES],
    states: *const BodyState,
    inverse_inertia: *const Mat3,
    len: usize,
) -> [[F; 8]; 4] {
    use std::arch::x86_64::{_mm256_loadu_ps, _mm256_setzero_ps, _mm256_store_ps};
    // SAFETY: AVX2 is present (the caller's contract).
    let mut rows = [[unsafe { _mm256_setzero_ps() }; LANES]; 4];
    for l in 0..LANES {
        let k = bodies[l] as usize;
        assert!(k < len, "body index out of range");
        // SAFETY: in range (checked); floats 0..8 and 5..13 of the 13 of a state, 0..8 and
        // 1..9 of the 9 of a matrix: every load lies inside the element.
        unsafe {
            let s = states.add(k) as *const f32;
            let m = inverse_inertia.add(k) as *const f32;
            rows[0][l] = _mm256_loadu_ps(s);
            rows[1][l] = _mm256_loadu_ps(s.add(5));
            rows[2][l] = _mm256_loadu_ps(m);
            rows[3][l] = _mm256_loadu_ps(m.add(1));
        }
    }
    let mut out = [[F::default(); 8]; 4];
    for (tile, rows) in out.iter_mut().zip(rows) {
        // SAFETY: AVX2 is present.
        let cols = unsafe { transpose(rows) };
        for (f, c) in tile.iter_mut().zip(cols) {
            // SAFETY: `F` is eight floats aligned to 32 bytes.
            unsafe { _mm256_store_ps(f.0.as_mut_ptr(), c) };
        }
    }
    out
}

/// The 8 x 8 transpose of `rows`: element `j` of output `i` is element `i` of row `j`.
///
/// # Safety
/// AVX2 is present (the caller is compiled with it).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn transpose(r: [std::arch::x86_64::__m256; 8]) -> [std::arch::x86_64::__m256; 8] {
    use std::arch::x86_64::{
        _mm256_permute2f128_ps, _mm256_shuffle_ps, _mm256_unpackhi_ps, _mm256_unpacklo_ps,
    };
    // SAFETY: AVX2 is present (the caller's contract); the shuffles only move bits.
    unsafe {
        let t0 = _mm256_unpacklo_ps(r[0], r[1]);
        let t1 = _mm256_unpackhi_ps(r[0], r[1]);
        let t2 = _mm256_unpacklo_ps(r[2], r[3]);
        let t3 = _mm256_unpackhi_ps(r[2], r[3]);
        let t4 = _mm256_unpacklo_ps(r[4], r[5]);
        let t5 = _mm256_unpackhi_ps(r[4], r[5]);
        let t6 = _mm256_unpacklo_ps(r[6], r[7]);
        let t7 = _mm256_unpackhi_ps(r[6], r[7]);
        let u0 = _mm256_shuffle_ps::<0x44>(t0, t2);
        let u1 = _mm256_shuffle_ps::<0xEE>(t0, t2);
        let u2 = _mm256_shuffle_ps::<0x44>(t1, t3);
        let u3 = _mm256_shuffle_ps::<0xEE>(t1, t3);
        let u4 = _mm256_shuffle_ps::<0x44>(t4, t6);
        let u5 = _mm256_shuffle_ps::<0xEE>(t4, t6);
        let u6 = _mm256_shuffle_ps::<0x44>(t5, t7);
        let u7 = _mm256_shuffle_ps::<0xEE>(t5, t7);
        [
            _mm256_permute2f128_ps::<0x20>(u0, u4),
            _mm256_permute2f128_ps::<0x20>(u1, u5),
            _mm256_permute2f128_ps::<0x20>(u2, u6),
            _mm256_permute2f128_ps::<0x20>(u3, u7),
            _mm256_permute2f128_ps::<0x31>(u0, u4),
            _mm256_permute2f128_ps::<0x31>(u1, u5),
            _mm256_permute2f128_ps::<0x31>(u2, u6),
            _mm256_permute2f128_ps::<0x31>(u3, u7),
        ]
    }
}
