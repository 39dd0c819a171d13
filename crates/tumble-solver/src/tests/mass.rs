//! Mass properties of boxes and what bodies make of them: inverse mass and inertia, infinite
//! mass for fixed and kinematic bodies, locked axes, and boxes too small or too large.

use tumble_geometry::nalgebra::UnitQuaternion;
use tumble_geometry::{Cuboid, Pose, Vec3};

use super::reference::{M, m64};
use super::{assert_close, body, material};
use crate::{BodyKind, Locks, MassProperties, Mat3};

#[test]
fn box_mass_and_moments_follow_m_over_12_times_the_sum_of_squared_sizes() {
    // Sizes 2a, 2b, 2c = 0.4, 1.2, 3.0 at density 2.5: m = 2.5 * 1.44 = 3.6 kg,
    // Ix = m (1.2^2 + 3^2) / 12 = 3.132, Iy = m (0.4^2 + 3^2) / 12 = 2.748,
    // Iz = m (0.4^2 + 1.2^2) / 12 = 0.48.
    let p = MassProperties::cuboid(&Cuboid::new(Vec3::new(0.2, 0.6, 1.5)), 2.5).unwrap();
    assert_close("mass", p.mass.into(), 3.6, 1e-5);
    for (k, want) in [3.132, 2.748, 0.48].into_iter().enumerate() {
        assert_close("moment", p.principal_inertia[k].into(), want, 1e-5 * want);
        assert_close(
            "inverse moment",
            p.inverse_principal_inertia()[k].into(),
            1.0 / want,
            1e-5 / want,
        );
    }
    assert_close("inverse mass", p.inverse_mass().into(), 1.0 / 3.6, 1e-6);
}

#[test]
fn dynamic_bodies_invert_their_mass_and_others_have_none() {
    let half = Vec3::new(0.2, 0.6, 1.5);
    let pose = Pose::from_parts(
        Vec3::new(1.0, 2.0, 3.0).into(),
        UnitQuaternion::from_euler_angles(0.5, 0.1, -0.4),
    );
    let dynamic = body(BodyKind::Dynamic, half, pose, 2.5, material(0.5, 0.0));
    assert_close("1 / m", dynamic.inverse_mass.into(), 1.0 / 3.6, 1e-6);
    assert_eq!(
        dynamic.inverse_mass_axes(),
        Vec3::repeat(dynamic.inverse_mass)
    );
    // inertia_local inverts the inverse moments back.
    for (k, want) in [3.132, 2.748, 0.48].into_iter().enumerate() {
        assert_close(
            "moment",
            dynamic.inertia_local()[k].into(),
            want,
            1e-5 * want,
        );
    }
    // World inverse inertia R D^-1 R^T.
    let r = m64(&pose.rotation.to_rotation_matrix().into_inner());
    let want =
        r * M::from_diagonal(&tumble_geometry::nalgebra::Vector3::new(
            1.0 / 3.132,
            1.0 / 2.748,
            1.0 / 0.48,
        )) * r.transpose();
    let got = m64(&dynamic.inverse_inertia_world());
    assert!(
        (got - want).abs().max() < 1e-5 * want.abs().max(),
        "{got} vs {want}"
    );
    for kind in [BodyKind::Fixed, BodyKind::Kinematic] {
        let b = body(kind, half, pose, 2.5, material(0.5, 0.0));
        assert_eq!(b.inverse_mass, 0.0);
        assert_eq!(b.inverse_inertia_local, Vec3::zeros());
        assert_eq!(b.inverse_mass_axes(), Vec3::zeros());
        assert_eq!(b.inverse_inertia_world(), Mat3::zeros());
        // Infinite moments are reported as 0, not as infinity.
        assert_eq!(b.inertia_local(), Vec3::zeros());
        assert!(!b.is_dynamic());
    }
    assert!(dynamic.is_dynamic());
}

#[test]
fn locks_zero_their_axes_of_the_inverse_mass_and_inertia() {
    let pose = Pose::from_parts(
        Vec3::zeros().into(),
        UnitQuaternion::from_euler_angles(0.5, 0.1, -0.4),
    );
    let mut b = body(
        BodyKind::Dynamic,
        Vec3::new(0.2, 0.6, 1.5),
        pose,
        2.5,
        material(0.5, 0.0),
    );
    let free = b.inverse_inertia_world();
    b.locks = Locks {
        translation: [true, false, true],
        rotation: [false, false, true],
    };
    assert_eq!(b.inverse_mass_axes(), Vec3::new(0.0, b.inverse_mass, 0.0));
    // P W P with P = diag(1, 1, 0): the z row and column go, the rest is the free tensor.
    let w = b.inverse_inertia_world();
    for i in 0..3 {
        for j in 0..3 {
            let want = if i == 2 || j == 2 { 0.0 } else { free[(i, j)] };
            assert_close("locked tensor", w[(i, j)].into(), want.into(), 1e-7);
        }
    }
    b.locks.rotation = [true; 3];
    assert_eq!(b.inverse_inertia_world(), Mat3::zeros());
    assert!(b.locks.any_rotation() && b.locks.all_rotations());
    b.locks.rotation = [false, true, false];
    assert!(b.locks.any_rotation() && !b.locks.all_rotations());
    b.locks.rotation = [false; 3];
    assert!(!b.locks.any_rotation() && !b.locks.all_rotations());
    assert_eq!(b.locks.rotation_mask(), Vec3::repeat(1.0));
    assert_eq!(b.locks.translation_mask(), Vec3::new(0.0, 1.0, 0.0));
}

#[test]
fn boxes_whose_inertia_underflows_or_overflows_are_rejected() {
    // A 2e-15 m box of density 1: the mass (8e-45 kg) is a positive subnormal, but its
    // moments m (b^2 + c^2) / 3 underflow to 0: no finite angular response exists.
    let tiny = MassProperties::cuboid(&Cuboid::new(Vec3::repeat(1e-15)), 1.0).unwrap_err();
    assert!(tiny.field.starts_with("inertia"), "{}", tiny.field);
    // A 2e12 m box: mass 8e36 kg is finite, its moments are not.
    let huge = MassProperties::cuboid(&Cuboid::new(Vec3::repeat(1e12)), 1.0).unwrap_err();
    assert!(huge.field.starts_with("inertia"), "{}", huge.field);
    // A box whose mass itself underflows names the mass.
    let e = MassProperties::cuboid(&Cuboid::new(Vec3::repeat(1e-20)), 1.0).unwrap_err();
    assert!(e.field.starts_with("mass"), "{}", e.field);
    let e = MassProperties::cuboid(&Cuboid::new(Vec3::new(-0.5, 0.5, 0.5)), 1.0).unwrap_err();
    assert_eq!(e.field, "half_extents.x");
    let e = MassProperties::cuboid(&Cuboid::new(Vec3::repeat(0.5)), 0.0).unwrap_err();
    assert_eq!(e.field, "density");
}
