//! An f64 reference of the contact kernels, written from their documented formulas rather than
//! from the precomputed rows: every row is `J = [-d, -(r_a x d), d, r_b x d]`, its effective
//! mass `1 / (J M^-1 J^T)` with `M^-1 = diag(m_a^-1 per axis, I_a^-1, m_b^-1 per axis, I_b^-1)`,
//! and an impulse `lambda` changes the velocities by `M^-1 J^T lambda`.
//!
//! The reference reads only the constraint's primary data (normal, tangents, anchors, base
//! separations, inverse masses and inertias, coefficients, impulses); the arms, pushes and
//! effective masses that `prepare_contact` precomputes are rebuilt here, so a wrong
//! precomputation or a wrong use of it in the kernels shows up as a mismatch.

use tumble_geometry::nalgebra::{Matrix3, Vector3};

use crate::{BodyState, ContactConstraint, Mat3};
use tumble_geometry::Vec3;

pub(crate) type V = Vector3<f64>;
pub(crate) type M = Matrix3<f64>;

pub(crate) fn v64(v: &Vec3) -> V {
    v.map(f64::from)
}

pub(crate) fn m64(m: &Mat3) -> M {
    m.map(f64::from)
}

/// A body's velocity state and in-step deltas in f64.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RefState {
    pub v: V,
    pub w: V,
    pub dp: V,
    pub dq: M,
}

impl RefState {
    pub fn from(s: &BodyState) -> Self {
        Self {
            v: v64(&s.linear_velocity),
            w: v64(&s.angular_velocity),
            dp: v64(&s.delta_position),
            dq: m64(&s.delta_rotation.to_rotation_matrix().into_inner()),
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub(crate) struct RefPoint {
    pub ra: V,
    pub rb: V,
    pub base: f64,
    pub normal: f64,
    pub tangent: [f64; 2],
    pub total: f64,
    pub relative_velocity: f64,
}

/// Declares [`Branches`] from one list of its counters, each with the name the coverage
/// check prints: the struct, its sum and its named counts then cannot disagree on the fields.
macro_rules! branches {
    ($($field:ident: $name:literal),* $(,)?) => {
        /// Which branches a pass took, so a randomized test can show that it exercised all of
        /// them.
        #[derive(Clone, Copy, Debug, Default)]
        pub(crate) struct Branches {
            $(pub $field: usize,)*
        }

        impl Branches {
            pub fn add(&mut self, o: &Branches) {
                $(self.$field += o.$field;)*
            }

            /// Every branch's name and count, in declaration order.
            pub fn counts(&self) -> Vec<(&'static str, usize)> {
                vec![$(($name, self.$field)),*]
            }
        }
    };
}

branches! {
    speculative: "speculative",
    biased: "biased",
    push_out_capped: "push-out cap",
    within_slop: "within slop",
    relaxed: "relaxed",
    normal_released: "normal released",
    friction_sliding: "friction sliding",
    friction_sticking: "friction sticking",
    tilt_capped: "tilt capped",
    tilt_free: "tilt free",
    second_visit: "patch visited again after friction",
    patch_sliding: "patch sliding, no second visit",
    without_friction: "biased pass without friction (FrictionPasses::RelaxOnly)",
    restitution_applied: "restitution applied",
    restitution_slow: "restitution slow",
    restitution_no_push: "restitution no push",
}

#[derive(Clone, Debug)]
pub(crate) struct RefConstraint {
    pub n: V,
    pub t: [V; 2],
    pub inv_mass_a: V,
    pub inv_mass_b: V,
    pub ia: M,
    pub ib: M,
    pub friction: f64,
    pub restitution: f64,
    pub bias_rate: f64,
    pub mass_scale: f64,
    pub impulse_scale: f64,
    pub slop: f64,
    pub patch_radius: f64,
    pub tilt: [f64; 2],
    pub points: Vec<RefPoint>,
}

impl RefConstraint {
    /// The reference of `c`, from its primary data only.
    pub fn from(c: &ContactConstraint) -> Self {
        let points = c.points[..c.point_count as usize]
            .iter()
            .map(|p| RefPoint {
                ra: v64(&p.anchor_a),
                rb: v64(&p.anchor_b),
                base: p.base_separation.into(),
                normal: p.normal_impulse.into(),
                tangent: p.tangent_impulse.map(f64::from),
                total: p.total_normal_impulse.into(),
                relative_velocity: p.relative_velocity.into(),
            })
            .collect();
        Self {
            n: v64(&c.normal),
            t: [v64(&c.tangent1), v64(&c.tangent2)],
            inv_mass_a: v64(&c.inverse_mass_a),
            inv_mass_b: v64(&c.inverse_mass_b),
            ia: m64(&c.inverse_inertia_a),
            ib: m64(&c.inverse_inertia_b),
            friction: c.friction.into(),
            restitution: c.restitution.into(),
            bias_rate: c.softness.bias_rate.into(),
            mass_scale: c.softness.mass_scale.into(),
            impulse_scale: c.softness.impulse_scale.into(),
            slop: c.slop.into(),
            patch_radius: c.patch_radius.into(),
            tilt: c.tilt_impulse.map(f64::from),
            points,
        }
    }

    /// `J M^-1 J^T` of direction `d` at point `p`.
    pub fn inverse_effective_mass(&self, p: &RefPoint, d: &V) -> f64 {
        let (arm_a, arm_b) = (p.ra.cross(d), p.rb.cross(d));
        let linear: f64 = (0..3)
            .map(|k| d[k] * d[k] * (self.inv_mass_a[k] + self.inv_mass_b[k]))
            .sum();
        linear + arm_a.dot(&(self.ia * arm_a)) + arm_b.dot(&(self.ib * arm_b))
    }

    /// The effective mass, 0 when neither body can move along the row.
    pub fn effective_mass(&self, p: &RefPoint, d: &V) -> f64 {
        let k = self.inverse_effective_mass(p, d);
        if k > 0.0 { 1.0 / k } else { 0.0 }
    }

    /// `J v`: the relative velocity of the two surfaces at `p` along `d`.
    pub fn velocity(&self, a: &RefState, b: &RefState, p: &RefPoint, d: &V) -> f64 {
        let va = a.v + a.w.cross(&p.ra);
        let vb = b.v + b.w.cross(&p.rb);
        d.dot(&(vb - va))
    }

    /// `v += M^-1 J^T lambda`: `-lambda d` at A's anchor, `+lambda d` at B's.
    pub fn apply(&self, a: &mut RefState, b: &mut RefState, p: &RefPoint, d: &V, lambda: f64) {
        let impulse = d * lambda;
        a.v -= self.inv_mass_a.component_mul(&impulse);
        a.w -= self.ia * p.ra.cross(&impulse);
        b.v += self.inv_mass_b.component_mul(&impulse);
        b.w += self.ib * p.rb.cross(&impulse);
    }

    /// An angular impulse `tau` on B and `-tau` on A.
    pub fn apply_torque(&self, a: &mut RefState, b: &mut RefState, tau: &V) {
        a.w -= self.ia * tau;
        b.w += self.ib * tau;
    }

    /// The current separation of point `i`, from the start-of-step geometry and the deltas.
    pub fn separation(&self, a: &RefState, b: &RefState, p: &RefPoint) -> f64 {
        let moved_b = b.dp + b.dq * p.rb - p.rb;
        let moved_a = a.dp + a.dq * p.ra - p.ra;
        // base + (r_b - r_a) . n is the separation at the start of the step.
        p.base + (p.rb - p.ra).dot(&self.n) + (moved_b - moved_a).dot(&self.n)
    }

    pub fn warm_start(&mut self, a: &mut RefState, b: &mut RefState) {
        let (n, t) = (self.n, self.t);
        for i in 0..self.points.len() {
            let p = self.points[i];
            self.points[i].total += p.normal;
            self.apply(a, b, &p, &n, p.normal);
            if self.friction > 0.0 {
                self.apply(a, b, &p, &t[0], p.tangent[0]);
                self.apply(a, b, &p, &t[1], p.tangent[1]);
            }
        }
        let tau = t[0] * self.tilt[0] + t[1] * self.tilt[1];
        self.apply_torque(a, b, &tau);
    }

    /// One pass: normal rows, tilt rows of a patch, then (with `friction`) friction, and for
    /// a patch with friction that does not slide at every point the normal and tilt rows once
    /// more.
    pub fn solve(
        &mut self,
        a: &mut RefState,
        b: &mut RefState,
        inv_h: f64,
        use_bias: bool,
        max_push_out: f64,
        friction: bool,
    ) -> Branches {
        let mut br = Branches::default();
        let patch = self.patch_radius > 0.0;
        self.normal_rows(a, b, inv_h, use_bias, max_push_out, &mut br);
        if patch {
            self.tilt_rows(a, b, &mut br);
        }
        if !friction {
            br.without_friction += 1;
            return br;
        }
        if self.friction == 0.0 {
            return br;
        }
        let all_slide = self.friction_rows(a, b, &mut br);
        if patch && all_slide {
            br.patch_sliding += 1;
        }
        if patch && !all_slide {
            br.second_visit += 1;
            self.normal_rows(a, b, inv_h, use_bias, max_push_out, &mut br);
            self.tilt_rows(a, b, &mut br);
        }
        br
    }

    fn normal_rows(
        &mut self,
        a: &mut RefState,
        b: &mut RefState,
        inv_h: f64,
        use_bias: bool,
        max_push_out: f64,
        br: &mut Branches,
    ) {
        let n = self.n;
        for i in 0..self.points.len() {
            let p = self.points[i];
            let s = self.separation(a, b, &p);
            let (bias, mass_scale, impulse_scale) = if s > 0.0 {
                br.speculative += 1;
                (s * inv_h, 1.0, 0.0)
            } else if use_bias {
                br.biased += 1;
                let wanted = self.mass_scale * self.bias_rate * (s + self.slop).min(0.0);
                if wanted < -max_push_out {
                    br.push_out_capped += 1;
                }
                if s + self.slop >= 0.0 {
                    br.within_slop += 1;
                }
                (
                    wanted.max(-max_push_out),
                    self.mass_scale,
                    self.impulse_scale,
                )
            } else {
                br.relaxed += 1;
                (0.0, 1.0, 0.0)
            };
            let vn = self.velocity(a, b, &p, &n);
            let m = self.effective_mass(&p, &n);
            let delta = -m * (mass_scale * vn + bias) - impulse_scale * p.normal;
            let accumulated = (p.normal + delta).max(0.0);
            if p.normal + delta < 0.0 {
                br.normal_released += 1;
            }
            let applied = accumulated - p.normal;
            self.points[i].normal = accumulated;
            self.points[i].total += applied;
            self.apply(a, b, &p, &n, applied);
        }
    }

    fn tilt_rows(&mut self, a: &mut RefState, b: &mut RefState, br: &mut Branches) {
        let t = self.t;
        {
            let least = self
                .points
                .iter()
                .map(|p| p.normal)
                .fold(f64::INFINITY, f64::min);
            let limit = self.points.len() as f64 * self.patch_radius * least.max(0.0);
            let relative = b.w - a.w;
            let old = self.tilt;
            let mut new = [0.0; 2];
            for k in 0..2 {
                // Like every row, a tilt row neither body can turn along has no mass.
                let inverse = t[k].dot(&((self.ia + self.ib) * t[k]));
                let mass = if inverse > 0.0 { 1.0 / inverse } else { 0.0 };
                new[k] = old[k] - mass * relative.dot(&t[k]);
            }
            let (new, capped) = clamp_to_disc(new, limit);
            if capped {
                br.tilt_capped += 1;
            } else {
                br.tilt_free += 1;
            }
            self.tilt = new;
            let tau = t[0] * (new[0] - old[0]) + t[1] * (new[1] - old[1]);
            self.apply_torque(a, b, &tau);
        }
    }

    /// The friction rows; true when every point slides.
    fn friction_rows(&mut self, a: &mut RefState, b: &mut RefState, br: &mut Branches) -> bool {
        let t = self.t;
        let mut all_slide = true;
        for i in 0..self.points.len() {
            let p = self.points[i];
            let old = p.tangent;
            let mut new = [0.0; 2];
            for k in 0..2 {
                new[k] = old[k] - self.effective_mass(&p, &t[k]) * self.velocity(a, b, &p, &t[k]);
            }
            let (new, sliding) = clamp_to_disc(new, self.friction * p.normal);
            if sliding {
                br.friction_sliding += 1;
            } else {
                br.friction_sticking += 1;
                all_slide = false;
            }
            self.points[i].tangent = new;
            self.apply(a, b, &p, &t[0], new[0] - old[0]);
            self.apply(a, b, &p, &t[1], new[1] - old[1]);
        }
        all_slide
    }

    pub fn restitution(&mut self, a: &mut RefState, b: &mut RefState, threshold: f64) -> Branches {
        let mut br = Branches::default();
        if self.restitution == 0.0 {
            return br;
        }
        let n = self.n;
        for i in 0..self.points.len() {
            let p = self.points[i];
            if p.relative_velocity > -threshold {
                br.restitution_slow += 1;
                continue;
            }
            if p.total == 0.0 {
                br.restitution_no_push += 1;
                continue;
            }
            br.restitution_applied += 1;
            let vn = self.velocity(a, b, &p, &n);
            let m = self.effective_mass(&p, &n);
            let delta = -m * (vn + self.restitution * p.relative_velocity);
            let accumulated = (p.normal + delta).max(0.0);
            let applied = accumulated - p.normal;
            self.points[i].normal = accumulated;
            self.points[i].total += applied;
            self.apply(a, b, &p, &n, applied);
        }
        br
    }
}

/// `v` scaled onto the disc of radius `limit` when it lies outside it (the Coulomb and tilt
/// clamps), and whether it did.
fn clamp_to_disc(v: [f64; 2], limit: f64) -> ([f64; 2], bool) {
    let length = (v[0] * v[0] + v[1] * v[1]).sqrt();
    if length > limit {
        let scale = if length > 0.0 { limit / length } else { 0.0 };
        ([v[0] * scale, v[1] * scale], true)
    } else {
        (v, false)
    }
}
