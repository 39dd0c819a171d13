//! The gyroscopic term of Euler's equations, integrated implicitly.
//!
//! Torque-free rotation obeys `I dw/dt = (I w) x w` in the body frame. Explicit Euler on this
//! gains energy, and one step of backward Euler (Catto, "Numerical Methods", GDC 2015; used by
//! Bullet, rapier and Jolt) loses angular momentum at a rate of `(h |w|)^2 / 2` per step:
//! about 8% over 10 s for a box tumbling at 2 rad/s with 4 substeps at 60 Hz. The implicit
//! midpoint rule solved here conserves every quadratic invariant of the free motion, so both
//! `|L|^2` and the kinetic energy `L . I^-1 L / 2` are kept up to round-off.

use tumble_geometry::{Real, Vec3};

use crate::Mat3;

/// Newton iterations for the midpoint equation; the residual shrinks quadratically, so three
/// reach f32 round-off for `h |w|` up to about 1 (a quarter turn per substep).
pub const NEWTON_ITERATIONS: usize = 3;

/// Skew-symmetric cross-product matrix: `skew(a) b = a x b`.
fn skew(a: &Vec3) -> Mat3 {
    Mat3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// Advances the body-frame angular velocity `w0` by `h` under the gyroscopic torque of
/// principal moments `inertia`, with the implicit midpoint rule
/// `I (w1 - w0) = h (I wm) x wm`, `wm = (w0 + w1) / 2`.
pub fn gyroscopic_midpoint(inertia: &Vec3, w0: &Vec3, h: Real) -> Vec3 {
    let moments = Mat3::from_diagonal(inertia);
    let mut w1 = *w0;
    for _ in 0..NEWTON_ITERATIONS {
        let wm = (w0 + w1) * 0.5;
        let lm = inertia.component_mul(&wm);
        let residual = inertia.component_mul(&(w1 - w0)) - lm.cross(&wm) * h;
        // d/dw [(I w) x w] = skew(I w) - skew(w) I, and dwm/dw1 = 1/2.
        let jacobian = moments - (skew(&lm) - skew(&wm) * moments) * (0.5 * h);
        match jacobian.try_inverse() {
            Some(inverse) => w1 -= inverse * residual,
            None => break,
        }
    }
    w1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn energy(i: &Vec3, w: &Vec3) -> Real {
        0.5 * w.dot(&i.component_mul(w))
    }

    #[test]
    fn midpoint_keeps_momentum_and_energy_of_a_tumbling_box() {
        // A 1 x 2 x 3 box (m = 6): principal moments m (b^2 + c^2) / 12 and so on.
        let inertia = Vec3::new(6.5, 5.0, 2.5);
        let mut w = Vec3::new(0.3, 2.0, 0.4); // near the unstable middle axis: it tumbles
        let (l0, e0) = (inertia.component_mul(&w).norm(), energy(&inertia, &w));
        let h = 1.0 / 240.0;
        for _ in 0..2400 {
            w = gyroscopic_midpoint(&inertia, &w, h);
        }
        let (l1, e1) = (inertia.component_mul(&w).norm(), energy(&inertia, &w));
        // The midpoint rule conserves both exactly; what remains is f32 round-off over 2400
        // steps (about 1e-5 relative), far inside the 1e-3 bound. Backward Euler would lose
        // several percent here.
        assert!((l1 - l0).abs() < 1e-3 * l0, "|L| {l0} -> {l1}");
        assert!((e1 - e0).abs() < 1e-3 * e0, "E {e0} -> {e1}");
        // And the box did tumble: the spin left the middle axis.
        assert!((w.y - 2.0).abs() > 0.1, "{w}");
    }
}
