//! `prepare_contact` and `store_impulses`: every field of a constraint against its definition
//! (anchors, base separation, effective masses from `J M^-1 J^T`, warm-start projections,
//! approach speed, tilt rows, coefficient and softness selection), and `patch_radius` on
//! regular polygons.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{ContactPoint, Point3, Pose, Real, Rot, Vec3};

use super::reference::{RefConstraint, m64, v64};
use super::{assert_close, body, manifold, material, unit};
use crate::{
    Body, BodyKind, BodyState, Contact, Locks, Mat3, PrepareContext, Softness, SolverKind,
    mix_friction, mix_restitution, patch_radius, prepare_contact, tangent_basis,
};

/// Distinct sentinel softnesses, so the test can tell which one a constraint got.
const DYNAMIC_SOFTNESS: Softness = Softness {
    bias_rate: 11.0,
    mass_scale: 0.7,
    impulse_scale: 0.3,
};
const STATIC_SOFTNESS: Softness = Softness {
    bias_rate: 22.0,
    mass_scale: 0.8,
    impulse_scale: 0.2,
};

fn context(kind: SolverKind, warm_start_scale: Real) -> PrepareContext {
    PrepareContext {
        kind,
        h: 1.0 / 240.0,
        contact_softness: DYNAMIC_SOFTNESS,
        static_softness: STATIC_SOFTNESS,
        slop: 0.004,
        warm_start_scale,
    }
}

#[test]
fn prepared_fields_follow_their_definitions() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for case in 0..400 {
        let kinds = [
            [BodyKind::Dynamic, BodyKind::Dynamic],
            [BodyKind::Fixed, BodyKind::Dynamic],
            [BodyKind::Dynamic, BodyKind::Kinematic],
        ][case % 3];
        let normal = unit(&mut rng);
        let mut bodies: Vec<Body> = kinds
            .iter()
            .enumerate()
            .map(|(i, &kind)| {
                let centre = normal * i as Real + Vec3::new(1.0, -2.0, 0.5);
                let friction = if rng.random_bool(0.25) {
                    0.0
                } else {
                    rng.random_range(0.05..1.0)
                };
                body(
                    kind,
                    Vec3::new(
                        rng.random_range(0.2..1.0),
                        rng.random_range(0.2..1.0),
                        rng.random_range(0.2..1.0),
                    ),
                    Pose::from_parts(
                        centre.into(),
                        Rot::from_scaled_axis(unit(&mut rng) * rng.random_range(0.0..3.0)),
                    ),
                    rng.random_range(0.5..3.0),
                    material(friction, rng.random_range(0.0..1.0)),
                )
            })
            .collect();
        if rng.random_bool(0.2) {
            bodies[0].locks = Locks {
                translation: [true, false, false],
                rotation: [false, true, false],
            };
        }
        // Extra bodies before the pair, so body indices are not just 0 and 1.
        let spare = bodies[1];
        bodies.insert(0, spare);
        let (ia, ib) = (1u32, 2u32);
        let inertia: Vec<Mat3> = bodies.iter().map(Body::inverse_inertia_world).collect();
        let states: Vec<BodyState> = bodies
            .iter()
            .map(|_| {
                BodyState::moving(
                    unit(&mut rng) * rng.random_range(0.0..3.0),
                    unit(&mut rng) * rng.random_range(0.0..3.0),
                )
            })
            .collect();
        let (t1, t2) = tangent_basis(&normal);
        let count = rng.random_range(1..=4);
        let mid = (bodies[1].pose.translation.vector + bodies[2].pose.translation.vector) * 0.5;
        let points: Vec<(Point3, Real, u32)> = (0..count)
            .map(|id| {
                let p = mid + t1 * rng.random_range(-0.5..0.5) + t2 * rng.random_range(-0.5..0.5);
                (p.into(), rng.random_range(-0.03..0.03), 10 + id)
            })
            .collect();
        let mut contact = Contact::new(ia, ib, manifold(normal, &points));
        for imp in contact.impulses.iter_mut() {
            imp.normal = rng.random_range(0.0..2.0);
            // Friction as a world vector, partly off the tangent plane (a turned normal).
            imp.friction = unit(&mut rng) * rng.random_range(0.0..2.0);
        }
        contact.tilt_impulse = unit(&mut rng) * 0.7;
        let contacts = [Contact::default(), contact];
        let kind = if case % 2 == 0 {
            SolverKind::SoftStep
        } else {
            SolverKind::Baumgarte
        };
        let scale = if case % 5 == 0 { 0.0 } else { 1.0 };
        let ctx = context(kind, scale);
        let c = prepare_contact(&bodies, &inertia, &states, &contacts, 1, &ctx);

        let (a, b) = (&bodies[1], &bodies[2]);
        assert_eq!((c.body_a, c.body_b, c.contact), (ia, ib, 1));
        assert_eq!((c.dynamic_a, c.dynamic_b), (a.is_dynamic(), b.is_dynamic()));
        assert_eq!((c.normal, c.tangent1, c.tangent2), (normal, t1, t2));
        assert_eq!(c.inverse_mass_a, a.inverse_mass_axes());
        assert_eq!(c.inverse_mass_b, b.inverse_mass_axes());
        assert_eq!(c.inverse_inertia_a, a.inverse_inertia_world());
        assert_eq!(c.inverse_inertia_b, b.inverse_inertia_world());
        let mu = mix_friction(a.material.friction, b.material.friction);
        assert_eq!(c.friction, mu);
        assert_eq!(
            c.restitution,
            mix_restitution(a.material.restitution, b.material.restitution)
        );
        // Soft step: contacts with a fixed or kinematic body get the stiffer static softness;
        // Baumgarte has one rigid softness and the slop, the soft step no slop.
        let expected_softness = match kind {
            SolverKind::SoftStep if a.is_dynamic() && b.is_dynamic() => DYNAMIC_SOFTNESS,
            SolverKind::SoftStep => STATIC_SOFTNESS,
            SolverKind::Baumgarte => DYNAMIC_SOFTNESS,
        };
        assert_eq!(c.softness, expected_softness, "case {case}");
        assert_eq!(
            c.slop,
            if kind == SolverKind::Baumgarte {
                0.004
            } else {
                0.0
            }
        );
        assert_eq!(c.point_count, count);
        assert_eq!(
            c.patch_radius,
            patch_radius(contacts[1].manifold.points(), &normal)
        );

        let r = RefConstraint::from(&c);
        let close = |what: &str, got: Real, want: f64| {
            // f32 against f64 on values of order 1: 1e-4 relative is ~1000 ulp.
            assert_close(
                &format!("case {case}: {what}"),
                got.into(),
                want,
                1e-4 * (1.0 + want.abs()),
            );
        };
        let (ca, cb) = (
            v64(&a.pose.translation.vector),
            v64(&b.pose.translation.vector),
        );
        let (sa, sb) = (&states[1], &states[2]);
        for (i, (p, q)) in c
            .points
            .iter()
            .zip(&r.points)
            .enumerate()
            .take(count as usize)
        {
            let point = v64(&points[i].0.coords);
            for k in 0..3 {
                close("anchor a", p.anchor_a[k], point[k] - ca[k]);
                close("anchor b", p.anchor_b[k], point[k] - cb[k]);
            }
            // base + (r_b - r_a) . n is minus the depth: the separation at the start.
            close(
                "base separation",
                p.base_separation,
                -f64::from(points[i].1) - (q.rb - q.ra).dot(&v64(&normal)),
            );
            close(
                "normal mass",
                p.normal_mass,
                r.effective_mass(q, &v64(&normal)),
            );
            let arm = q.ra.cross(&v64(&normal));
            for k in 0..3 {
                close("normal arm a", p.normal_row.arm_a[k], arm[k]);
                close(
                    "normal push a",
                    p.normal_row.push_a[k],
                    (m64(&c.inverse_inertia_a) * arm)[k],
                );
            }
            let warm = &contacts[1].impulses[i];
            close(
                "warm normal",
                p.normal_impulse,
                f64::from(scale * warm.normal),
            );
            assert_eq!(
                p.total_normal_impulse, 0.0,
                "a new step has applied nothing yet"
            );
            if mu > 0.0 {
                for (k, t) in [t1, t2].iter().enumerate() {
                    close(
                        "tangent mass",
                        p.tangent_mass[k],
                        r.effective_mass(q, &v64(t)),
                    );
                    // The stored world vector is projected on this step's tangents.
                    close(
                        "warm friction",
                        p.tangent_impulse[k],
                        f64::from(scale) * v64(&warm.friction).dot(&v64(t)),
                    );
                }
            } else {
                // Frictionless: one row per point, nothing carried on the others.
                assert_eq!(p.tangent_mass, [0.0; 2]);
                assert_eq!(p.tangent_impulse, [0.0; 2]);
                assert_eq!(p.tangent_rows, [Default::default(); 2]);
            }
            // Approach speed: the relative velocity of the two surface points along n.
            let va = v64(&sa.linear_velocity) + v64(&sa.angular_velocity).cross(&q.ra);
            let vb = v64(&sb.linear_velocity) + v64(&sb.angular_velocity).cross(&q.rb);
            close(
                "relative velocity",
                p.relative_velocity,
                (vb - va).dot(&v64(&normal)),
            );
        }
        let (iia, iib) = (m64(&c.inverse_inertia_a), m64(&c.inverse_inertia_b));
        for (k, t) in [t1, t2].iter().enumerate() {
            let t = v64(t);
            let inverse = t.dot(&((iia + iib) * t));
            let want = if inverse > 0.0 { 1.0 / inverse } else { 0.0 };
            close("tilt mass", c.tilt_mass[k], want);
            close(
                "tilt impulse",
                c.tilt_impulse[k],
                // Carried only onto a patch with tilt rows (see tests/tilt.rs).
                if c.patch_radius > 0.0 {
                    f64::from(scale) * v64(&contacts[1].tilt_impulse).dot(&t)
                } else {
                    0.0
                },
            );
            for j in 0..3 {
                close("tilt push a", c.tilt_push_a[k][j], (iia * t)[j]);
                close("tilt push b", c.tilt_push_b[k][j], (iib * t)[j]);
            }
        }
    }
}

#[test]
fn a_row_no_body_can_move_along_has_zero_mass_not_infinite() {
    // A box that can neither translate along y nor rotate rests on a fixed floor: nothing can
    // move along the normal, so the normal row's mass is 0 (an infinite mass would turn the
    // first pass into NaN), and nothing can tilt.
    let floor = super::floor(material(0.5, 0.0));
    let mut cube = super::unit_cube(1.0, Pose::translation(0.0, 0.5, 0.0), material(0.5, 0.0));
    cube.locks = Locks {
        translation: [false, true, false],
        rotation: [true; 3],
    };
    let bodies = [floor, cube];
    let inertia: Vec<Mat3> = bodies.iter().map(Body::inverse_inertia_world).collect();
    let contacts = [Contact::new(0, 1, super::floor_center(&cube))];
    let states = [BodyState::default(); 2];
    let ctx = context(SolverKind::SoftStep, 1.0);
    let c = prepare_contact(&bodies, &inertia, &states, &contacts, 0, &ctx);
    assert_eq!(c.points[0].normal_mass, 0.0);
    assert_eq!(c.tilt_mass, [0.0; 2]);
    // Along x the box still slides: its friction row has the box's mass (1 kg).
    let along_x = if c.tangent1.x.abs() > 0.5 { 0 } else { 1 };
    assert_close(
        "x friction mass",
        c.points[0].tangent_mass[along_x].into(),
        1.0,
        1e-5,
    );
}

#[test]
fn store_impulses_writes_world_vectors_that_prepare_reads_back() {
    let floor = super::floor(material(0.6, 0.0));
    let cube = super::unit_cube(2.0, Pose::translation(0.0, 0.5, 0.0), material(0.6, 0.0));
    let bodies = [floor, cube];
    let inertia: Vec<Mat3> = bodies.iter().map(Body::inverse_inertia_world).collect();
    let states = [BodyState::default(); 2];
    let mut contacts = [Contact::new(0, 1, super::floor_corners(&cube))];
    let ctx = context(SolverKind::SoftStep, 1.0);
    let mut c = prepare_contact(&bodies, &inertia, &states, &contacts, 0, &ctx);
    for (i, p) in c.points.iter_mut().enumerate() {
        p.normal_impulse = 1.0 + i as Real;
        p.tangent_impulse = [0.3 * i as Real, -0.2];
        p.total_normal_impulse = 5.0 + i as Real;
    }
    c.tilt_impulse = [0.25, -0.5];
    c.store_impulses(&mut contacts[0]);
    for i in 0..4 {
        let stored = &contacts[0].impulses[i];
        assert_eq!(stored.normal, 1.0 + i as Real);
        assert_eq!(contacts[0].total_normal_impulse[i], 5.0 + i as Real);
        // The friction impulse as a world vector: t1 * lambda_1 + t2 * lambda_2.
        let want = c.tangent1 * (0.3 * i as Real) - c.tangent2 * 0.2;
        assert!(
            (stored.friction - want).norm() < 1e-6,
            "{} vs {want}",
            stored.friction
        );
    }
    let tilt = c.tangent1 * 0.25 - c.tangent2 * 0.5;
    assert!((contacts[0].tilt_impulse - tilt).norm() < 1e-6);
    // Next step, same normal: the projections give back the same row impulses.
    let again = prepare_contact(&bodies, &inertia, &states, &contacts, 0, &ctx);
    for i in 0..4 {
        assert_close(
            "normal",
            again.points[i].normal_impulse.into(),
            1.0 + i as f64,
            1e-6,
        );
        assert_close(
            "t1",
            again.points[i].tangent_impulse[0].into(),
            0.3 * i as f64,
            1e-6,
        );
        assert_close("t2", again.points[i].tangent_impulse[1].into(), -0.2, 1e-6);
    }
    assert_close("tilt 1", again.tilt_impulse[0].into(), 0.25, 1e-6);
    assert_close("tilt 2", again.tilt_impulse[1].into(), -0.5, 1e-6);
}

fn polygon(
    centre: Vec3,
    normal: &Vec3,
    radius: Real,
    n: usize,
    lift: &[Real],
) -> Vec<ContactPoint> {
    let (t1, t2) = tangent_basis(normal);
    (0..n)
        .map(|k| {
            let angle = 2.0 * std::f32::consts::PI * k as Real / n as Real + 0.3;
            let p = centre + (t1 * angle.cos() + t2 * angle.sin()) * radius + normal * lift[k];
            ContactPoint {
                position: p.into(),
                depth: 0.01,
                id: k as u32,
            }
        })
        .collect()
}

#[test]
fn patch_radius_is_the_inscribed_radius_of_regular_patches() {
    let normal = Vec3::new(0.36, 0.48, 0.8);
    let centre = Vec3::new(3.0, -1.0, 2.0);
    // Points may sit at different heights along the normal (midpoints of unequal depths);
    // only the in-plane distances count.
    let lift = [0.05, -0.03, 0.02, -0.04];
    // A square of circumradius R has inradius R cos(pi / 4); an equilateral triangle R / 2.
    let square = polygon(centre, &normal, 0.8, 4, &lift);
    assert_close(
        "square",
        patch_radius(&square, &normal).into(),
        0.8 * std::f64::consts::FRAC_1_SQRT_2,
        1e-5,
    );
    let triangle = polygon(centre, &normal, 0.6, 3, &lift);
    assert_close(
        "triangle",
        patch_radius(&triangle, &normal).into(),
        0.3,
        1e-5,
    );
    // Two points form an edge, one a vertex: no patch, no tilt resistance.
    let edge = polygon(centre, &normal, 0.6, 2, &lift);
    assert_eq!(patch_radius(&edge, &normal), 0.0);
    assert_eq!(patch_radius(&edge[..1], &normal), 0.0);
}

#[test]
fn the_softness_and_slop_follow_the_solver_and_the_body_kinds() {
    let dynamic = super::unit_cube(1.0, Pose::translation(0.0, 0.5, 0.0), material(0.5, 0.0));
    let upper = super::unit_cube(1.0, Pose::translation(0.0, 1.5, 0.0), material(0.5, 0.0));
    let fixed = super::floor(material(0.5, 0.0));
    let kinematic = body(
        BodyKind::Kinematic,
        Vec3::repeat(0.5),
        Pose::translation(0.0, 1.5, 0.0),
        1.0,
        material(0.5, 0.0),
    );
    let states = [BodyState::default(); 2];
    for (a, b, soft_expected) in [
        (dynamic, upper, DYNAMIC_SOFTNESS),
        (fixed, dynamic, STATIC_SOFTNESS),
        (dynamic, kinematic, STATIC_SOFTNESS),
    ] {
        let bodies = [a, b];
        let inertia: Vec<Mat3> = bodies.iter().map(Body::inverse_inertia_world).collect();
        let contacts = [Contact::new(0, 1, super::floor_center(&b))];
        let prepare = |kind| {
            let ctx = context(kind, 1.0);
            prepare_contact(&bodies, &inertia, &states, &contacts, 0, &ctx)
        };
        let soft = prepare(SolverKind::SoftStep);
        assert_eq!(soft.softness, soft_expected);
        assert_eq!(soft.slop, 0.0);
        let pgs = prepare(SolverKind::Baumgarte);
        assert_eq!(pgs.softness, DYNAMIC_SOFTNESS);
        assert_eq!(pgs.slop, 0.004);
    }
}
