//! The per-constraint kernels (`warm_start_contact`, `solve_contact`, `restitution_contact`)
//! against the f64 reference on randomized constraints, and the physical laws every pass must
//! keep whatever its inputs: momentum, the Coulomb disc, the speculative gap, the tilt bound.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Manifold, Point3, Pose, Real, Rot, Vec3};

use super::reference::{Branches, RefConstraint, RefState, V, m64, v64};
use super::{body, manifold, material, unit};
use crate::{
    Body, BodyKind, BodyState, Contact, ContactConstraint, Locks, Mat3, PassContext,
    PrepareContext, Softness, SolverKind, prepare_contact, restitution_contact, solve_contact,
    tangent_basis, warm_start_contact,
};

fn vec_in(rng: &mut ChaCha8Rng, r: Real) -> Vec3 {
    Vec3::new(
        rng.random_range(-r..r),
        rng.random_range(-r..r),
        rng.random_range(-r..r),
    )
}

fn random_rotation(rng: &mut ChaCha8Rng, max_angle: Real) -> Rot {
    Rot::from_scaled_axis(unit(rng) * rng.random_range(0.0..max_angle))
}

fn random_body(rng: &mut ChaCha8Rng, kind: BodyKind, at: Vec3) -> Body {
    let friction = if rng.random_bool(0.2) {
        0.0
    } else {
        rng.random_range(0.1..1.2)
    };
    let restitution = if rng.random_bool(0.3) {
        0.0
    } else {
        rng.random_range(0.1..1.0)
    };
    let mut b = body(
        kind,
        Vec3::new(
            rng.random_range(0.2..1.5),
            rng.random_range(0.2..1.5),
            rng.random_range(0.2..1.5),
        ),
        Pose::from_parts(at.into(), random_rotation(rng, 3.0)),
        rng.random_range(0.5..3.0),
        material(friction, restitution),
    );
    if kind == BodyKind::Dynamic && rng.random_bool(0.15) {
        b.locks = Locks {
            translation: std::array::from_fn(|_| rng.random_bool(0.3)),
            rotation: std::array::from_fn(|_| rng.random_bool(0.4)),
        };
    }
    b
}

/// A random constraint between two boxes, as `prepare_contact` builds it, with its bodies'
/// states and the pass settings.
pub(super) struct Case {
    c: ContactConstraint,
    a: BodyState,
    b: BodyState,
    pass: PassContext,
    threshold: Real,
}

impl Case {
    /// The constraint, the two states, the pass and the restitution threshold.
    pub(super) fn parts(self) -> (ContactConstraint, BodyState, BodyState, PassContext, Real) {
        (self.c, self.a, self.b, self.pass, self.threshold)
    }
}

/// The reference's pass over `r` with the kernel pass's parameters.
fn reference_pass(
    r: &mut RefConstraint,
    ra: &mut RefState,
    rb: &mut RefState,
    pass: &PassContext,
) -> Branches {
    r.solve(
        ra,
        rb,
        pass.inv_h.into(),
        pass.use_bias,
        pass.max_push_out.into(),
        pass.friction,
    )
}

/// The inputs of `prepare_contact` for one random pair of boxes: the two bodies (indices 0
/// and 1), their states at the start of the step, their contact and the step's values.
pub(super) struct PrepareInputs {
    pub(super) bodies: [Body; 2],
    pub(super) states: [BodyState; 2],
    pub(super) contact: Contact,
    pub(super) ctx: PrepareContext,
    count: u32,
    inv_h: Real,
}

/// Random [`PrepareInputs`]: any body kinds, locks, materials and point counts, face patches
/// at rest and anything else, soft step or Baumgarte.
pub(super) fn random_prepare_inputs(rng: &mut ChaCha8Rng) -> PrepareInputs {
    let kinds = match rng.random_range(0..10) {
        0..=4 => (BodyKind::Dynamic, BodyKind::Dynamic),
        5 | 6 => (BodyKind::Fixed, BodyKind::Dynamic),
        7 => (BodyKind::Kinematic, BodyKind::Dynamic),
        _ => (BodyKind::Dynamic, BodyKind::Fixed),
    };
    let normal = unit(rng);
    let ca = vec_in(rng, 5.0);
    let cb = ca + normal * rng.random_range(0.4..2.0) + vec_in(rng, 0.3);
    let bodies = [random_body(rng, kinds.0, ca), random_body(rng, kinds.1, cb)];
    let mid = (ca + cb) * 0.5;
    let (t1, t2) = tangent_basis(&normal);
    // A third of the cases are loaded face patches nearly at rest (a box on a box): four
    // overlapping points on a square, slow bodies. The others are anything.
    let resting = rng.random_bool(0.35);
    let count = if resting { 4 } else { rng.random_range(1..=4) };
    let half = rng.random_range(0.2..0.6);
    let points: Vec<(Point3, Real, u32)> = (0..count)
        .map(|id| {
            let p = if resting {
                let (x, y) = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)][id as usize];
                mid + (t1 * x + t2 * y) * half
            } else {
                mid + t1 * rng.random_range(-0.6..0.6) + t2 * rng.random_range(-0.6..0.6)
            } + normal * rng.random_range(-0.02..0.02);
            let depth = if resting {
                rng.random_range(0.0..0.02)
            } else {
                rng.random_range(-0.04..0.04)
            };
            (p.into(), depth, id)
        })
        .collect();
    let mut contact = Contact::new(0, 1, manifold(normal, &points));
    for imp in contact.impulses.iter_mut() {
        imp.normal = rng.random_range(0.0..3.0);
        imp.friction = t1 * rng.random_range(-3.0..3.0) + t2 * rng.random_range(-3.0..3.0);
    }
    contact.tilt_impulse = t1 * rng.random_range(-1.0..1.0) + t2 * rng.random_range(-1.0..1.0);
    let moving = |rng: &mut ChaCha8Rng, b: &Body| {
        if b.kind == BodyKind::Fixed {
            BodyState::default()
        } else {
            let speed = if resting { 0.3 } else { 3.0 };
            BodyState::moving(vec_in(rng, speed), vec_in(rng, speed))
        }
    };
    let states = [moving(rng, &bodies[0]), moving(rng, &bodies[1])];

    let inv_h: Real = rng.random_range(60.0..480.0);
    let h = 1.0 / inv_h;
    let kind = if rng.random_bool(0.5) {
        SolverKind::SoftStep
    } else {
        SolverKind::Baumgarte
    };
    let (contact_softness, static_softness) = match kind {
        SolverKind::SoftStep => (
            Softness::new(rng.random_range(5.0..60.0), rng.random_range(0.0..10.0), h),
            Softness::new(rng.random_range(5.0..60.0), rng.random_range(0.0..10.0), h),
        ),
        SolverKind::Baumgarte => {
            let rigid = Softness {
                bias_rate: rng.random_range(0.1..0.5) * inv_h,
                ..Softness::RIGID
            };
            (rigid, rigid)
        }
    };
    let ctx = PrepareContext {
        kind,
        h,
        contact_softness,
        static_softness,
        slop: rng.random_range(0.0..0.01),
        warm_start_scale: 1.0,
    };
    PrepareInputs {
        bodies,
        states,
        contact,
        ctx,
        count,
        inv_h,
    }
}

pub(super) fn random_case(rng: &mut ChaCha8Rng) -> Case {
    let PrepareInputs {
        bodies,
        mut states,
        contact,
        ctx,
        count,
        inv_h,
    } = random_prepare_inputs(rng);
    let inertia: Vec<Mat3> = bodies.iter().map(Body::inverse_inertia_world).collect();
    let mut c = prepare_contact(&bodies, &inertia, &states, &[contact], 0, &ctx);
    // Impulses applied earlier in the step; some points have not pushed at all.
    for p in c.points[..count as usize].iter_mut() {
        p.total_normal_impulse = if rng.random_bool(0.25) {
            0.0
        } else {
            rng.random_range(0.0..1.0)
        };
    }
    // The bodies have moved since the start of the step.
    for (s, b) in states.iter_mut().zip(&bodies) {
        if b.kind != BodyKind::Fixed {
            s.delta_position = vec_in(rng, 0.03);
            s.delta_rotation = random_rotation(rng, 0.05);
        }
    }
    Case {
        c,
        a: states[0],
        b: states[1],
        pass: {
            let use_bias = rng.random_bool(0.7);
            PassContext {
                inv_h,
                use_bias,
                max_push_out: rng.random_range(0.2..3.0),
                // FrictionPasses::RelaxOnly's biased passes in some cases: relax passes
                // always solve friction.
                friction: !use_bias || rng.random_bool(0.7),
            }
        },
        threshold: rng.random_range(0.2..2.0),
    }
}

/// Compares the kernel's constraint and states with the reference's. f32 against f64 over a
/// few dozen operations on values of order 1-10 agrees to about 1e-5, up to 2.4e-4 where a
/// speculative bias `s / h` multiplies the f32 round-off of the separation by 480; 5e-4
/// relative covers that and is still far below what a wrong sign, factor or row changes
/// (order 1).
#[track_caller]
#[allow(clippy::too_many_arguments)]
fn agree(
    step: &str,
    case: usize,
    c: &ContactConstraint,
    a: &BodyState,
    b: &BodyState,
    r: &RefConstraint,
    ra: &RefState,
    rb: &RefState,
) {
    let close = |what: &str, got: Real, want: f64| {
        let tol = 5e-4 * (1.0 + want.abs());
        assert!(
            (f64::from(got) - want).abs() <= tol,
            "case {case}, {step}: {what} = {got}, reference {want}"
        );
    };
    let close3 = |what: &str, got: &Vec3, want: &V| {
        for k in 0..3 {
            close(&format!("{what}[{k}]"), got[k], want[k]);
        }
    };
    close3("v_a", &a.linear_velocity, &ra.v);
    close3("w_a", &a.angular_velocity, &ra.w);
    close3("v_b", &b.linear_velocity, &rb.v);
    close3("w_b", &b.angular_velocity, &rb.w);
    for (i, (p, q)) in c.points.iter().zip(&r.points).enumerate() {
        close(&format!("normal impulse {i}"), p.normal_impulse, q.normal);
        close(
            &format!("total impulse {i}"),
            p.total_normal_impulse,
            q.total,
        );
        close(
            &format!("tangent impulse {i}.0"),
            p.tangent_impulse[0],
            q.tangent[0],
        );
        close(
            &format!("tangent impulse {i}.1"),
            p.tangent_impulse[1],
            q.tangent[1],
        );
    }
    close("tilt 0", c.tilt_impulse[0], r.tilt[0]);
    close("tilt 1", c.tilt_impulse[1], r.tilt[1]);
}

#[test]
fn kernels_match_the_reference_on_random_constraints() {
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let mut seen = Branches::default();
    for case in 0..1500 {
        let (mut c, mut a, mut b, pass, threshold) = random_case(&mut rng).parts();
        let mut r = RefConstraint::from(&c);
        let (mut ra, mut rb) = (RefState::from(&a), RefState::from(&b));

        warm_start_contact(&mut c, &mut a, &mut b);
        r.warm_start(&mut ra, &mut rb);
        agree("warm start", case, &c, &a, &b, &r, &ra, &rb);

        solve_contact(&mut c, &mut a, &mut b, &pass);
        seen.add(&reference_pass(&mut r, &mut ra, &mut rb, &pass));
        agree("first pass", case, &c, &a, &b, &r, &ra, &rb);

        // A second pass starts from accumulated impulses (the clamps act on the sums).
        solve_contact(&mut c, &mut a, &mut b, &pass);
        seen.add(&reference_pass(&mut r, &mut ra, &mut rb, &pass));
        agree("second pass", case, &c, &a, &b, &r, &ra, &rb);

        let relax = PassContext {
            use_bias: false,
            friction: true,
            ..pass
        };
        solve_contact(&mut c, &mut a, &mut b, &relax);
        seen.add(&reference_pass(&mut r, &mut ra, &mut rb, &relax));
        agree("relax pass", case, &c, &a, &b, &r, &ra, &rb);

        restitution_contact(&mut c, &mut a, &mut b, threshold);
        seen.add(&r.restitution(&mut ra, &mut rb, threshold.into()));
        agree("restitution", case, &c, &a, &b, &r, &ra, &rb);
    }
    // Every branch of the kernels ran many times, so each comparison above was exercised.
    let counts = seen.counts();
    for &(name, n) in &counts {
        assert!(n >= 30, "branch {name} ran {n} times: {counts:?}");
    }
}

#[test]
fn contact_passes_conserve_linear_and_angular_momentum() {
    // Between two free dynamic bodies every row applies equal and opposite impulses at one
    // point (and equal and opposite torques for the tilt rows), so whatever the impulses are,
    // the total momentum and the angular momentum about any fixed point stay the same.
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    let mut checked = 0;
    for _ in 0..1000 {
        let (mut c, mut a, mut b, pass, threshold) = random_case(&mut rng).parts();
        // Locked axes take up momentum (they are constraints to the world): skip them.
        let free = c.dynamic_a
            && c.dynamic_b
            && c.inverse_mass_a.min() > 0.0
            && c.inverse_mass_b.min() > 0.0
            && c.inverse_inertia_a.determinant().abs() > 1e-9
            && c.inverse_inertia_b.determinant().abs() > 1e-9;
        if !free {
            continue;
        }
        // Anchors are point - centre for both bodies, so with A's centre at the origin B's
        // centre is anchor_a - anchor_b (the same for every point).
        let cb = v64(&(c.points[0].anchor_a - c.points[0].anchor_b));
        let bodies = [
            (c.inverse_mass_a.x, c.inverse_inertia_a, V::zeros()),
            (c.inverse_mass_b.x, c.inverse_inertia_b, cb),
        ];
        let momentum = |a: &BodyState, b: &BodyState| {
            let (mut p, mut l) = (V::zeros(), V::zeros());
            for (s, &(inverse_mass, inverse_inertia, centre)) in [a, b].into_iter().zip(&bodies) {
                let linear = v64(&s.linear_velocity) / f64::from(inverse_mass);
                let inertia = m64(&inverse_inertia).try_inverse().unwrap();
                p += linear;
                l += inertia * v64(&s.angular_velocity) + centre.cross(&linear);
            }
            (p, l)
        };
        let (p0, l0) = momentum(&a, &b);
        let scale = 1.0 + p0.norm() + l0.norm();
        warm_start_contact(&mut c, &mut a, &mut b);
        solve_contact(&mut c, &mut a, &mut b, &pass);
        let relax = PassContext {
            use_bias: false,
            friction: true,
            ..pass
        };
        solve_contact(&mut c, &mut a, &mut b, &relax);
        restitution_contact(&mut c, &mut a, &mut b, threshold);
        let (p1, l1) = momentum(&a, &b);
        // f32 round-off of a few dozen impulses of order 1: 1e-4 relative.
        assert!((p1 - p0).norm() < 1e-4 * scale, "momentum {p0} -> {p1}");
        assert!(
            (l1 - l0).norm() < 1e-4 * scale,
            "angular momentum {l0} -> {l1}"
        );
        checked += 1;
    }
    // About a third of the random cases are two free dynamic bodies.
    assert!(checked >= 200, "only {checked} free pairs");
}

/// A unit cube of 1 kg on the fixed floor, at rest, touching it through `geometry`'s manifold,
/// prepared for `kind` at substep `h` with `softness` and friction `mu`; the floor's and the
/// cube's states are returned with the constraint.
fn prepared_on_floor(
    mu: Real,
    geometry: fn(&Body) -> Manifold,
    kind: SolverKind,
    h: Real,
    softness: Softness,
) -> (ContactConstraint, BodyState, BodyState) {
    let m = material(mu, 0.0);
    let bodies = [
        super::floor(m),
        super::unit_cube(1.0, Pose::translation(0.0, 0.5, 0.0), m),
    ];
    let inertia: Vec<Mat3> = bodies.iter().map(Body::inverse_inertia_world).collect();
    let contacts = [Contact::new(0, 1, geometry(&bodies[1]))];
    let states = [BodyState::default(); 2];
    let ctx = PrepareContext {
        kind,
        h,
        contact_softness: softness,
        static_softness: softness,
        slop: 0.0,
        warm_start_scale: 1.0,
    };
    let c = prepare_contact(&bodies, &inertia, &states, &contacts, 0, &ctx);
    (c, states[0], states[1])
}

/// A unit cube of 1 kg on the fixed floor, one point under its centre, prepared with
/// `softness` and friction `mu`; the cube's state is returned with the constraint.
fn cube_on_floor(mu: Real, softness: Softness) -> (ContactConstraint, BodyState, BodyState) {
    prepared_on_floor(
        mu,
        super::floor_center,
        SolverKind::SoftStep,
        1.0 / 240.0,
        softness,
    )
}

/// A pass at substep rate `inv_h`, feeding position error back when `use_bias`, under a
/// 3 m/s push-out cap.
fn pass_at(inv_h: Real, use_bias: bool) -> PassContext {
    PassContext {
        inv_h,
        use_bias,
        max_push_out: 3.0,
        friction: true,
    }
}

#[test]
fn a_frictionless_warm_start_applies_only_the_normal_impulses() {
    // Friction 0 removes the friction rows: whatever the tangent slots hold, the warm start
    // pushes along the normal only.
    let (mut c, mut floor, mut cube) = cube_on_floor(0.0, Softness::RIGID);
    c.points[0].normal_impulse = 0.5;
    c.points[0].tangent_impulse = [0.3, -0.4];
    warm_start_contact(&mut c, &mut floor, &mut cube);
    assert_eq!(cube.linear_velocity, Vec3::new(0.0, 0.5, 0.0));
    assert_eq!(cube.angular_velocity, Vec3::zeros());
    assert_eq!(c.points[0].total_normal_impulse, 0.5);
}

#[test]
fn an_exactly_touching_point_is_solved_as_a_soft_contact_not_a_speculative_one() {
    // s = 0 is not apart: the soft row takes mass_scale of the approach speed away in one
    // pass (a speculative row would take all of it), leaving impulse_scale of it.
    let softness = Softness::new(30.0, 1.0, 1.0 / 240.0);
    let (mut c, mut floor, mut cube) = cube_on_floor(0.0, softness);
    // The cube's bottom lies on the floor: base + (r_b - r_a) . n = -depth = 0 exactly.
    let p = c.points[0];
    assert_eq!(
        p.base_separation + (p.anchor_b - p.anchor_a).dot(&c.normal),
        0.0
    );
    cube.linear_velocity = Vec3::new(0.0, -1.0, 0.0);
    let pass = pass_at(240.0, true);
    solve_contact(&mut c, &mut floor, &mut cube, &pass);
    assert!(
        (cube.linear_velocity.y + softness.impulse_scale).abs() < 1e-6,
        "{}",
        cube.linear_velocity.y
    );
    // Apart by 1 mm, the same approach is speculative: it may close the gap, no more.
    let (mut c, mut floor, mut cube) = cube_on_floor(0.0, softness);
    c.points[0].base_separation += 0.001;
    cube.linear_velocity = Vec3::new(0.0, -1.0, 0.0);
    solve_contact(&mut c, &mut floor, &mut cube, &pass);
    // -gap / h = -0.24 m/s, up to the f32 round-off of a 1 m separation times 240 / s.
    assert!(
        (cube.linear_velocity.y + 0.24).abs() < 1e-4,
        "{}",
        cube.linear_velocity.y
    );
}

#[test]
fn a_sliding_point_is_held_at_the_coulomb_limit_against_its_motion() {
    // 1 kg cube sliding at 2 m/s along x with 0.1 N s of normal impulse and mu = 0.4: the
    // friction impulse is 0.04 N s against x, so the centre loses 0.04 m/s; the point below
    // the centre lies on a lever, so the cube also starts to tip forward.
    let (mut c, mut floor, mut cube) = cube_on_floor(0.4, Softness::RIGID);
    c.points[0].normal_impulse = 0.1;
    cube.linear_velocity = Vec3::new(2.0, 0.0, 0.0);
    let relaxed = pass_at(240.0, false);
    solve_contact(&mut c, &mut floor, &mut cube, &relaxed);
    let p = c.points[0];
    let friction = c.tangent1 * p.tangent_impulse[0] + c.tangent2 * p.tangent_impulse[1];
    assert!(
        (friction - Vec3::new(-0.04, 0.0, 0.0)).norm() < 1e-6,
        "{friction}"
    );
    assert!(
        (cube.linear_velocity.x - 1.96).abs() < 1e-6,
        "{}",
        cube.linear_velocity
    );
    // The torque r x F = (0, -0.5, 0) x (-0.04, 0, 0) = (0, 0, -0.02) N m s, I = 1/6.
    assert!(
        (cube.angular_velocity - Vec3::new(0.0, 0.0, -0.12)).norm() < 1e-5,
        "{}",
        cube.angular_velocity
    );
}

#[test]
fn a_patch_whose_far_side_has_lifted_gets_no_tilt_torque() {
    // A cube on four corners whose two +x corners carry nothing: n r min(lambda) = 0, so the
    // tilt rows may add no torque and the rocking about z stays as the normal rows leave it.
    let (mut c, mut floor, mut cube) = prepared_on_floor(
        0.0,
        super::floor_corners,
        SolverKind::Baumgarte,
        1.0 / 60.0,
        Softness::RIGID,
    );
    assert!(
        c.patch_radius > 0.4,
        "a square patch of half size 0.5: {}",
        c.patch_radius
    );
    // Tipping about the -x edge (rotation about +z lifts the +x side).
    cube.angular_velocity = Vec3::new(0.0, 0.0, 1.0);
    cube.linear_velocity = Vec3::new(0.0, 0.5, 0.0);
    let pass = pass_at(60.0, false);
    solve_contact(&mut c, &mut floor, &mut cube, &pass);
    assert_eq!(c.tilt_impulse, [0.0; 2]);
    // The lifting corners are apart in velocity: they got no impulse, the others none
    // either (their surface points move up at 0.5 m/s).
    assert!(c.points[..4].iter().all(|p| p.normal_impulse == 0.0));
    assert_eq!(cube.angular_velocity, Vec3::new(0.0, 0.0, 1.0));
}
