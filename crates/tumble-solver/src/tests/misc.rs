//! Small contracts: the softness formulas, configuration defaults and validation, the
//! parameter checks, effect detection, and when a contact counts as touching.

use tumble_geometry::{Point3, Pose, Real, Vec3};

use super::{assert_close, body, manifold, material};
use crate::{
    BodyKind, Contact, DEFAULT_BAUMGARTE_ITERATIONS, Effects, Softness, SolverConfig, SolverKind,
    require_finite3, require_non_negative, require_positive,
};

#[test]
fn softness_matches_the_documented_implicit_spring_formulas() {
    // bias_rate = omega / (2 zeta + h omega), mass_scale = h omega (2 zeta + h omega) /
    // (1 + h omega (2 zeta + h omega)), impulse_scale = 1 / (1 + h omega (2 zeta + h omega)).
    for (hertz, zeta, h) in [
        (30.0, 10.0, 1.0 / 240.0),
        (60.0, 10.0, 1.0 / 360.0),
        (5.0, 0.5, 1.0 / 60.0),
        (90.0, 0.0, 1.0 / 360.0),
    ] {
        let s = Softness::new(hertz, zeta, h);
        let omega = 2.0 * std::f64::consts::PI * f64::from(hertz);
        let (zeta, h) = (f64::from(zeta), f64::from(h));
        let a1 = 2.0 * zeta + h * omega;
        let a2 = h * omega * a1;
        assert_close(
            "bias_rate",
            s.bias_rate.into(),
            omega / a1,
            1e-5 * omega / a1,
        );
        assert_close("mass_scale", s.mass_scale.into(), a2 / (1.0 + a2), 1e-6);
        assert_close(
            "impulse_scale",
            s.impulse_scale.into(),
            1.0 / (1.0 + a2),
            1e-6,
        );
    }
    // Zero hertz is a rigid constraint.
    assert_eq!(Softness::new(0.0, 10.0, 0.01), Softness::RIGID);
    assert_eq!(
        Softness::RIGID,
        Softness {
            bias_rate: 0.0,
            mass_scale: 1.0,
            impulse_scale: 0.0
        }
    );
}

#[test]
fn the_baumgarte_preset_is_one_substep_of_many_rigid_passes() {
    let b = SolverConfig::baumgarte();
    assert_eq!(b.kind, SolverKind::Baumgarte);
    assert_eq!(
        (b.iterations, b.substeps, b.relax_iterations),
        (DEFAULT_BAUMGARTE_ITERATIONS, 1, 0)
    );
    assert_eq!(SolverConfig::soft_step(), SolverConfig::default());
    let d = SolverConfig::default();
    assert_eq!(
        (d.kind, d.iterations, d.substeps, d.relax_iterations),
        (SolverKind::SoftStep, 1, 6, 1)
    );
    assert!(d.warm_start);
}

#[test]
fn validation_names_the_first_bad_field() {
    let d = SolverConfig::default();
    let field = |c: SolverConfig| c.validate().unwrap_err().field;
    assert_eq!(
        field(SolverConfig { iterations: 0, ..d }),
        "solver.iterations"
    );
    assert_eq!(field(SolverConfig { substeps: 0, ..d }), "solver.substeps");
    assert_eq!(
        field(SolverConfig {
            contact_hertz: 0.0,
            ..d
        }),
        "solver.contact_hertz"
    );
    assert_eq!(
        field(SolverConfig {
            damping_ratio: -1.0,
            ..d
        }),
        "solver.damping_ratio"
    );
    assert_eq!(
        field(SolverConfig {
            max_push_out: 0.0,
            ..d
        }),
        "solver.max_push_out"
    );
    assert_eq!(
        field(SolverConfig {
            baumgarte: -0.1,
            ..d
        }),
        "solver.baumgarte"
    );
    assert_eq!(
        field(SolverConfig {
            baumgarte: Real::NAN,
            ..d
        }),
        "solver.baumgarte"
    );
    assert_eq!(field(SolverConfig { slop: -0.001, ..d }), "solver.slop");
    assert_eq!(
        field(SolverConfig {
            restitution_threshold: Real::INFINITY,
            ..d
        }),
        "solver.restitution_threshold"
    );
    // The edges of the ranges are valid.
    for ok in [
        SolverConfig {
            iterations: 1,
            substeps: 1,
            ..d
        },
        SolverConfig {
            baumgarte: 0.0,
            damping_ratio: 0.0,
            slop: 0.0,
            restitution_threshold: 0.0,
            ..d
        },
        SolverConfig {
            baumgarte: 1.0,
            ..d
        },
    ] {
        ok.validate().unwrap();
    }
}

#[test]
fn parameter_checks_accept_exactly_their_ranges() {
    assert_eq!(require_positive("x", 2.5), Ok(2.5));
    assert_eq!(
        require_positive("x", Real::MIN_POSITIVE),
        Ok(Real::MIN_POSITIVE)
    );
    for bad in [0.0, -1.0, Real::NAN, Real::INFINITY] {
        let e = require_positive("x", bad).unwrap_err();
        assert_eq!((e.field, e.expected), ("x", "a finite number > 0"));
    }
    assert_eq!(require_non_negative("y", 0.0), Ok(0.0));
    assert_eq!(require_non_negative("y", 3.0), Ok(3.0));
    for bad in [-1e-9, Real::NAN, Real::INFINITY] {
        assert_eq!(require_non_negative("y", bad).unwrap_err().field, "y");
    }
    assert!(require_finite3("v", &Vec3::new(1.0, -2.0, 0.0)).is_ok());
    assert_eq!(
        require_finite3("v", &Vec3::new(1.0, Real::NAN, 0.0))
            .unwrap_err()
            .field,
        "v"
    );
}

#[test]
fn effects_need_two_rough_bodies_and_a_bouncy_one() {
    let b = |kind, friction, restitution| {
        body(
            kind,
            Vec3::repeat(0.5),
            Pose::identity(),
            1.0,
            material(friction, restitution),
        )
    };
    let g = Vec3::new(0.0, -9.81, 0.0);
    // Two smooth bodies: no friction rows (0 > 0 is false for both).
    let smooth = [b(BodyKind::Fixed, 0.0, 0.0), b(BodyKind::Dynamic, 0.0, 0.0)];
    let e = Effects::of_bodies(&smooth, &g);
    assert!(!e.friction && !e.restitution && e.gravity && e.rotation && !e.kinematic);
    let rough = [b(BodyKind::Fixed, 0.3, 0.0), b(BodyKind::Dynamic, 0.3, 0.2)];
    let e = Effects::of_bodies(&rough, &Vec3::zeros());
    assert!(e.friction && e.restitution && !e.gravity);
    // A fixed body alone needs no rotation; a kinematic one may turn.
    assert!(!Effects::of_bodies(&[b(BodyKind::Fixed, 0.3, 0.0)], &g).rotation);
    let e = Effects::of_bodies(&[b(BodyKind::Kinematic, 0.3, 0.0)], &g);
    assert!(e.rotation && e.kinematic);
}

#[test]
fn a_contact_touches_when_a_point_overlaps_or_pushed() {
    let point = |depth: Real| {
        manifold(
            Vec3::y(),
            &[
                (Point3::origin(), depth, 0),
                (Point3::new(1.0, 0.0, 0.0), -0.02, 1),
            ],
        )
    };
    assert!(Contact::new(0, 1, point(0.001)).is_touching());
    assert!(
        !Contact::new(0, 1, point(0.0)).is_touching(),
        "exactly touching is not overlapping"
    );
    assert!(!Contact::new(0, 1, point(-0.01)).is_touching());
    let mut pushed = Contact::new(0, 1, point(-0.01));
    pushed.total_normal_impulse[1] = 0.5;
    assert!(pushed.is_touching(), "a speculative point that pushed");
    // Only the manifold's points count.
    let mut stale = Contact::new(0, 1, point(-0.01));
    stale.total_normal_impulse[3] = 0.5;
    assert!(!stale.is_touching());
}
