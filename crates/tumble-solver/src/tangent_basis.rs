//! The two friction directions of a contact, derived deterministically from its normal.

use tumble_geometry::Vec3;

/// An orthonormal pair `(t1, t2)` with `t1 x t2 = n` for unit `n`.
///
/// Duff et al., "Building an Orthonormal Basis, Revisited" (JCGT 2017): branch-free and exact
/// to round-off. The basis flips across `n.z = 0` for normals with `n.x != 0`; this does not
/// disturb warm starting because friction impulses are carried between steps as world-space
/// vectors and re-projected onto whatever basis the new step uses.
pub fn tangent_basis(n: &Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let t1 = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let t2 = Vec3::new(b, sign + n.y * n.y * a, -n.y);
    (t1, t2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn basis_is_orthonormal_and_right_handed_for_random_normals() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let axes = [
            Vec3::x(),
            -Vec3::x(),
            Vec3::y(),
            -Vec3::y(),
            Vec3::z(),
            -Vec3::z(),
        ];
        let random = (0..1000).map(|_| {
            Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            )
            .normalize()
        });
        for n in axes.into_iter().chain(random) {
            let (t1, t2) = tangent_basis(&n);
            // Round-off of a handful of f32 operations: 1e-5 is ~100 ulp.
            assert!((t1.norm() - 1.0).abs() < 1e-5, "{n} {t1}");
            assert!((t2.norm() - 1.0).abs() < 1e-5);
            assert!(t1.dot(&n).abs() < 1e-5 && t2.dot(&n).abs() < 1e-5);
            assert!((t1.cross(&t2) - n).norm() < 1e-5);
        }
    }
}
