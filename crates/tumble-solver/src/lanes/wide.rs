//! Lane arithmetic: one `f32` per lane ([`F`]), lane masks ([`M`]), and 3-vectors,
//! quaternions and 3 x 3 matrices of lanes, each operation in the order nalgebra performs it
//! on one value, so that every lane gets the scalar bits.

use std::array::from_fn;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

use tumble_geometry::{Real, Vec3};

use super::LANES;
use crate::Mat3;

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
    pub(super) fn max(self, o: F) -> F {
        self.gt(o).select(self, o)
    }

    /// `contact_solver::min_of` lane by lane: `self < o ? self : o`.
    #[inline(always)]
    pub(super) fn min(self, o: F) -> F {
        o.gt(self).select(self, o)
    }

    #[inline(always)]
    pub(super) fn sqrt(self) -> F {
        F(from_fn(|i| self.0[i].sqrt()))
    }

    /// `self > o` lane by lane.
    #[inline(always)]
    pub(super) fn gt(self, o: F) -> M {
        M(from_fn(|i| if self.0[i] > o.0[i] { !0 } else { 0 }))
    }

    /// `self == o` lane by lane.
    #[inline(always)]
    pub(super) fn eq(self, o: F) -> M {
        M(from_fn(|i| if self.0[i] == o.0[i] { !0 } else { 0 }))
    }
}

impl M {
    pub(crate) const ALL: M = M([!0; LANES]);

    /// True when any lane is set.
    #[inline(always)]
    pub(super) fn any(self) -> bool {
        self.0.iter().fold(0, |acc, &m| acc | m) != 0
    }

    /// `a` where the mask is set, `b` elsewhere, bit for bit.
    #[inline(always)]
    pub(super) fn select(self, a: F, b: F) -> F {
        F(from_fn(|i| {
            Real::from_bits((a.0[i].to_bits() & self.0[i]) | (b.0[i].to_bits() & !self.0[i]))
        }))
    }

    #[inline(always)]
    pub(super) fn select3(self, a: V3, b: V3) -> V3 {
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
    pub(super) x: F,
    pub(super) y: F,
    pub(super) z: F,
}

impl V3 {
    /// Lane `l` set to `v`.
    #[inline(always)]
    pub(super) fn set(&mut self, l: usize, v: &Vec3) {
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
    pub(super) fn dot(&self, o: &V3) -> F {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// nalgebra's `cross`.
    #[inline(always)]
    pub(super) fn cross(&self, b: &V3) -> V3 {
        V3 {
            x: self.y * b.z - self.z * b.y,
            y: self.z * b.x - self.x * b.z,
            z: self.x * b.y - self.y * b.x,
        }
    }

    /// `component_mul`.
    #[inline(always)]
    pub(super) fn cmul(&self, o: &V3) -> V3 {
        V3 {
            x: self.x * o.x,
            y: self.y * o.y,
            z: self.z * o.z,
        }
    }

    /// Vector times a scalar per lane.
    #[inline(always)]
    pub(super) fn scale(&self, s: F) -> V3 {
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
pub(super) struct Q {
    pub(super) v: V3,
    pub(super) w: F,
}

impl Q {
    /// nalgebra's `UnitQuaternion * Vector3`: `t = 2 (q_v x v)`, then `(t w + q_v x t) + v`.
    #[inline(always)]
    pub(super) fn rotate(&self, v: &V3) -> V3 {
        let t = self.v.cross(v).scale(F::splat(2.0));
        let cross = self.v.cross(&t);
        t.scale(self.w) + cross + *v
    }
}

/// A 3 x 3 matrix per lane, row by row.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct M3(pub(super) [V3; 3]);

impl M3 {
    /// Lane `l` set to `m`.
    #[inline(always)]
    pub(super) fn set(&mut self, l: usize, m: &Mat3) {
        for (i, row) in self.0.iter_mut().enumerate() {
            row.set(l, &Vec3::new(m[(i, 0)], m[(i, 1)], m[(i, 2)]));
        }
    }

    /// nalgebra's `Matrix3 * Vector3`: row `i` is `(m_i0 x + m_i1 y) + m_i2 z`.
    #[inline(always)]
    pub(super) fn mul(&self, v: &V3) -> V3 {
        let row = |r: &V3| r.x * v.x + r.y * v.y + r.z * v.z;
        V3 {
            x: row(&self.0[0]),
            y: row(&self.0[1]),
            z: row(&self.0[2]),
        }
    }
}
