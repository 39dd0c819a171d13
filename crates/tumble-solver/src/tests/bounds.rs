//! The value bounds (`bounds.rs`): every range text names its limits, and the checks refuse
//! what lies outside.

use crate::bounds::*;
use crate::{Body, BodyKind, BodyState};
use tumble_geometry::{Pose, Real, Rot, Vec3};

/// The range texts quote the constants; a changed constant must change its text.
#[test]
fn range_texts_quote_the_constants() {
    for (text, values) in [
        (EXPECTED_POSITION, vec![format!("{MAX_POSITION}")]),
        (EXPECTED_SPEED, vec![format!("{MAX_SPEED}")]),
        (
            EXPECTED_HALF_EXTENT,
            vec![
                format!("{MIN_HALF_EXTENT:e}"),
                format!("{MAX_HALF_EXTENT:e}"),
            ],
        ),
        (
            EXPECTED_DENSITY,
            vec![format!("{MIN_DENSITY:e}"), format!("{MAX_DENSITY:e}")],
        ),
        (EXPECTED_IMPULSE, vec![format!("{MAX_IMPULSE:e}")]),
        (EXPECTED_GRAVITY, vec![format!("{MAX_GRAVITY:e}")]),
        (
            EXPECTED_DT,
            vec![format!("{MIN_DT:e}"), format!("{MAX_DT}")],
        ),
        (EXPECTED_SUBSTEPS, vec![format!("{MAX_SUBSTEPS}")]),
        (EXPECTED_ITERATIONS, vec![format!("{MAX_ITERATIONS}")]),
        (EXPECTED_DAMPING, vec![format!("{MAX_DAMPING:e}")]),
        (EXPECTED_FRICTION, vec![format!("{MAX_FRICTION}")]),
        (EXPECTED_MARGIN, vec![format!("{MAX_MARGIN}")]),
        (
            EXPECTED_RECYCLE_DISTANCE,
            vec![format!("{MAX_RECYCLE_DISTANCE}")],
        ),
        (
            EXPECTED_CONTACT_HERTZ,
            vec![format!("{MAX_CONTACT_HERTZ:e}")],
        ),
        (
            EXPECTED_DAMPING_RATIO,
            vec![format!("{MAX_DAMPING_RATIO:e}")],
        ),
        (EXPECTED_PUSH_OUT, vec![format!("{MAX_SPEED}")]),
        (EXPECTED_RESTITUTION_THRESHOLD, vec![format!("{MAX_SPEED}")]),
        (EXPECTED_SLOP, vec![format!("{MAX_SLOP}")]),
        (EXPECTED_FORCE, vec![format!("{MAX_FORCE:e}")]),
        (EXPECTED_TORQUE, vec![format!("{MAX_TORQUE:e}")]),
        (EXPECTED_FORCE_RESULT, vec![format!("{MAX_SPEED}")]),
        (EXPECTED_GRAVITY_SCALE, vec![format!("{MAX_GRAVITY_SCALE}")]),
    ] {
        for v in values {
            assert!(text.contains(&v), "{text:?} does not quote {v}");
        }
    }
}

/// The heaviest and lightest boxes the bounds allow have finite, normal masses and
/// moments, and so do their inverses: the arithmetic the ranges were chosen for.
#[test]
fn extreme_boxes_have_normal_masses_and_moments() {
    use crate::MassProperties;
    use tumble_geometry::Cuboid;
    for (h, density) in [
        (MIN_HALF_EXTENT, MIN_DENSITY),
        (MAX_HALF_EXTENT, MAX_DENSITY),
        (MIN_HALF_EXTENT, MAX_DENSITY),
        (MAX_HALF_EXTENT, MIN_DENSITY),
    ] {
        let m = MassProperties::cuboid(&Cuboid::new(Vec3::repeat(h)), density).unwrap();
        let inverse = m.inverse_principal_inertia();
        for x in [m.mass, 1.0 / m.mass]
            .into_iter()
            .chain(m.principal_inertia.iter().copied())
            .chain(inverse.iter().copied())
        {
            assert!(x.is_normal(), "h {h}, density {density}: {x}");
        }
    }
}

#[test]
fn out_of_range_values_are_refused_with_the_range() {
    let e = require_half_extents(&Vec3::new(0.5, 1e-4, 0.5)).unwrap_err();
    assert_eq!(e.field, "half_extents.y");
    assert_eq!(e.expected, EXPECTED_HALF_EXTENT);
    assert_eq!(require_density(2e5).unwrap_err().field, "density");
    assert!(require_density(Real::MIN_POSITIVE / 4.0).is_err());
    // 1e30 squared overflows f32; the f64 length still refuses it rather than NaN.
    let e = require_position("pose", &Vec3::new(1e30, 1e30, 0.0)).unwrap_err();
    assert_eq!(e.field, "pose");
    require_position("pose", &Vec3::new(MAX_POSITION, 0.0, 0.0)).unwrap();
    assert!(require_linear_speed("v", &Vec3::new(0.0, 400.5, 0.0)).is_err());
    require_linear_speed("v", &Vec3::new(0.0, -400.0, 0.0)).unwrap();
    // The default world (1/60 s, 6 substeps) carries pi/4 * 360 = 282.7 rad/s.
    assert!(require_angular_speed("w", &Vec3::new(283.0, 0.0, 0.0), 1.0 / 60.0, 6).is_err());
    require_angular_speed("w", &Vec3::new(282.0, 0.0, 0.0), 1.0 / 60.0, 6).unwrap();
    // A zero quaternion cannot be normalized; a tiny one squares to zero in f32.
    let zero = Rot::new_unchecked(tumble_geometry::nalgebra::Quaternion::new(
        0.0, 0.0, 0.0, 0.0,
    ));
    assert!(require_rotation("rotation", &zero).is_err());
    require_rotation("rotation", &Rot::identity()).unwrap();
}

#[test]
fn forces_torques_and_gravity_scales_are_bounded_absolutely_and_by_the_body() {
    let cube = |kind| {
        Body::new(
            kind,
            tumble_geometry::Cuboid::new(Vec3::repeat(0.5)),
            Pose::identity(),
            1.0,
            crate::Material::default(),
        )
        .unwrap()
    };
    let (dynamic, fixed) = (cube(BodyKind::Dynamic), cube(BodyKind::Fixed));
    let dt = 1.0 / 60.0;
    // The 1 kg cube: 24 kN adds 400 m/s in 1/60 s, the most allowed.
    require_force(&dynamic, &Vec3::new(0.0, 23_999.0, 0.0), dt).unwrap();
    let e = require_force(&dynamic, &Vec3::new(0.0, 24_001.0, 0.0), dt).unwrap_err();
    assert_eq!((e.field, e.expected), ("force", EXPECTED_FORCE_RESULT));
    // A fixed body does not move: only the absolute bound applies.
    require_force(&fixed, &Vec3::new(0.0, 1e19, 0.0), dt).unwrap();
    let e = require_force(&fixed, &Vec3::new(0.0, 2e20, 0.0), dt).unwrap_err();
    assert_eq!(e.expected, EXPECTED_FORCE);
    assert!(require_force(&dynamic, &Vec3::new(Real::NAN, 0.0, 0.0), dt).is_err());
    // Moments 1/6 kg m^2: 282.7 rad/s (pi/4 per substep, 6 substeps) in 1/60 s needs
    // 2827 N m.
    require_torque(&dynamic, &Vec3::new(2820.0, 0.0, 0.0), dt, 6).unwrap();
    let e = require_torque(&dynamic, &Vec3::new(2835.0, 0.0, 0.0), dt, 6).unwrap_err();
    assert_eq!((e.field, e.expected), ("torque", EXPECTED_TORQUE_RESULT));
    assert!(require_torque(&fixed, &Vec3::new(0.0, Real::INFINITY, 0.0), dt, 6).is_err());
    for ok in [0.0, -1.0, 2.0, MAX_GRAVITY_SCALE, -MAX_GRAVITY_SCALE] {
        require_gravity_scale(ok).unwrap();
    }
    for bad in [10.5, -11.0, Real::NAN, Real::INFINITY] {
        assert_eq!(
            require_gravity_scale(bad).unwrap_err().field,
            "gravity_scale"
        );
    }
}

#[test]
fn a_solved_state_beyond_the_bounds_is_named() {
    let body = Body::new(
        BodyKind::Dynamic,
        tumble_geometry::Cuboid::new(Vec3::repeat(0.5)),
        Pose::translation(MAX_POSITION - 1.0, 0.0, 0.0),
        1.0,
        crate::Material::default(),
    )
    .unwrap();
    let mut state = BodyState::default();
    assert_eq!(check_solved(&body, &state), None);
    // Two metres further would put the centre 1 m past the bound.
    state.delta_position = Vec3::new(2.0, 0.0, 0.0);
    assert_eq!(check_solved(&body, &state).unwrap().quantity, "position");
    state.delta_position = Vec3::zeros();
    state.angular_velocity = Vec3::new(0.0, Real::NAN, 0.0);
    assert_eq!(
        check_solved(&body, &state).unwrap().quantity,
        "angular_velocity"
    );
}
