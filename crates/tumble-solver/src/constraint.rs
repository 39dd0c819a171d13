//! Contact constraints: per manifold point a normal row and two friction rows, with effective
//! masses and anchors relative to the body centres, prepared once per step.
//!
//! Layout contract (mirrored by the GPU kernels): one [`ContactConstraint`] per manifold,
//! holding its bodies' inverse masses so the inner loops never touch cold body data, and up to
//! [`MAX_MANIFOLD_POINTS`] [`ConstraintPoint`]s. Anchors are world-space offsets from each body's
//! centre at the start of the step; the current separation is rebuilt every pass from the
//! bodies' delta positions and delta rotations (Box2D v3's `baseSeparation` scheme).

use tumble_geometry::{ContactPoint, MAX_MANIFOLD_POINTS, Real, Vec3};

use crate::{Body, BodyState, Contact, Mat3, Softness, SolverKind, tangent_basis};

/// The angular part of one row `J = [-d, -(r_a x d), d, r_b x d]`, precomputed so the passes
/// need dot products only: a row's velocity is `d . (v_b - v_a) + arm_b . w_b - arm_a . w_a`,
/// and an impulse `lambda` turns the bodies by `-push_a lambda` and `+push_b lambda`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AngularRow {
    /// `r_a x d`.
    pub arm_a: Vec3,
    /// `r_b x d`.
    pub arm_b: Vec3,
    /// `I_a^-1 (r_a x d)`: body A's change of angular velocity per unit impulse.
    pub push_a: Vec3,
    /// `I_b^-1 (r_b x d)`.
    pub push_b: Vec3,
}

impl AngularRow {
    /// The row of direction `d` at anchors `r_a`, `r_b` for world inverse inertias `ia`, `ib`.
    pub fn new(ia: &Mat3, ib: &Mat3, anchor_a: &Vec3, anchor_b: &Vec3, d: &Vec3) -> Self {
        let arm_a = anchor_a.cross(d);
        let arm_b = anchor_b.cross(d);
        Self {
            arm_a,
            arm_b,
            push_a: ia * arm_a,
            push_b: ib * arm_b,
        }
    }

    /// The angular part of `J M^-1 J^T`.
    pub fn angular_inverse_mass(&self) -> Real {
        self.arm_a.dot(&self.push_a) + self.arm_b.dot(&self.push_b)
    }
}

/// One point of a contact constraint.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ConstraintPoint {
    /// Contact point minus body A's centre, world axes, at the start of the step.
    pub anchor_a: Vec3,
    /// Contact point minus body B's centre, world axes, at the start of the step.
    pub anchor_b: Vec3,
    /// `separation - (anchor_b - anchor_a) . n`: adding the current `(c_b + r_b - c_a - r_a) . n`
    /// change gives the current separation (negative = overlap).
    pub base_separation: Real,
    /// `1 / (J M^-1 J^T)` of the normal row.
    pub normal_mass: Real,
    /// Effective masses of the two friction rows.
    pub tangent_mass: [Real; 2],
    /// Accumulated normal impulse of the current substep (>= 0).
    pub normal_impulse: Real,
    /// Accumulated friction impulses along `tangent1`, `tangent2`.
    pub tangent_impulse: [Real; 2],
    /// Normal impulse applied over the whole step (all substeps, warm starts, restitution).
    pub total_normal_impulse: Real,
    /// Normal relative velocity at preparation (negative = approaching), for restitution.
    pub relative_velocity: Real,
    /// Angular part of the normal row.
    pub normal_row: AngularRow,
    /// Angular parts of the two friction rows.
    pub tangent_rows: [AngularRow; 2],
}

/// The constraint of one manifold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactConstraint {
    /// Body A's index in the solver arrays.
    pub body_a: u32,
    /// Body B's index.
    pub body_b: u32,
    /// Index of the [`Contact`] this constraint came from (impulses are stored back there).
    pub contact: u32,
    /// Body A is dynamic: the solver writes its velocity.
    pub dynamic_a: bool,
    /// Body B is dynamic.
    pub dynamic_b: bool,
    /// Unit normal from A to B, fixed for the step.
    pub normal: Vec3,
    /// First friction direction.
    pub tangent1: Vec3,
    /// Second friction direction (`tangent1 x tangent2 = normal`).
    pub tangent2: Vec3,
    /// Body A's inverse mass per world axis (zero on locked axes).
    pub inverse_mass_a: Vec3,
    /// Body B's inverse mass per world axis.
    pub inverse_mass_b: Vec3,
    /// Body A's world inverse inertia at the start of the step.
    pub inverse_inertia_a: Mat3,
    /// Body B's world inverse inertia.
    pub inverse_inertia_b: Mat3,
    /// Combined friction coefficient; 0 removes the friction rows.
    pub friction: Real,
    /// Combined restitution; 0 skips the restitution pass.
    pub restitution: Real,
    /// Position feedback of the biased passes (soft step: the soft spring; Baumgarte:
    /// `bias_rate = beta / h`, rigid mass).
    pub softness: Softness,
    /// Overlap tolerated before position feedback starts (Baumgarte only; 0 for soft step).
    pub slop: Real,
    /// Number of valid points.
    pub point_count: u32,
    /// The points; only the first `point_count` are valid.
    pub points: [ConstraintPoint; MAX_MANIFOLD_POINTS],
    /// Radius of the disc inscribed in the contact patch, m: the lever arm up to which the
    /// patch carries a tilting torque (0 for fewer than three points: an edge or a point
    /// cannot resist tipping).
    pub patch_radius: Real,
    /// Effective masses of the two tilt rows (relative rotation about `tangent1`, `tangent2`).
    pub tilt_mass: [Real; 2],
    /// Accumulated angular impulses of the tilt rows, N m s.
    pub tilt_impulse: [Real; 2],
    /// `I_a^-1 t_k`: body A's change of angular velocity per unit tilt impulse about `t_k`.
    pub tilt_push_a: [Vec3; 2],
    /// `I_b^-1 t_k`.
    pub tilt_push_b: [Vec3; 2],
}

/// Step-wide values that [`prepare_contact`] needs.
#[derive(Clone, Copy, Debug)]
pub struct PrepareContext {
    /// Soft step or Baumgarte.
    pub kind: SolverKind,
    /// Substep length in s.
    pub h: Real,
    /// Softness of contacts between two dynamic bodies (Baumgarte: rigid, `beta / h`).
    pub contact_softness: Softness,
    /// Softness of contacts with a fixed or kinematic body (stiffer, as in Box2D v3).
    pub static_softness: Softness,
    /// Baumgarte slop in m.
    pub slop: Real,
    /// 1 to warm start, 0 to start from zero impulses.
    pub warm_start_scale: Real,
}

/// Inverse of a row's `J M^-1 J^T` for direction `d`, or 0 when both bodies are immovable
/// along it.
fn row_mass(constraint: &ContactConstraint, row: &AngularRow, d: &Vec3) -> Real {
    let d2 = d.component_mul(d);
    let k = constraint.inverse_mass_a.dot(&d2)
        + constraint.inverse_mass_b.dot(&d2)
        + row.angular_inverse_mass();
    if k > 0.0 { 1.0 / k } else { 0.0 }
}

/// The radius of the disc inscribed in a contact patch, approximated from its points: the
/// smallest in-plane distance from the centroid to a point, times `cos(pi / n)` (exact for a
/// regular polygon: a square patch of half size `a` gives `a`). Fewer than three points form
/// no patch and give 0.
pub fn patch_radius(points: &[ContactPoint], normal: &Vec3) -> Real {
    let n = points.len();
    if n < 3 {
        return 0.0;
    }
    let centroid = points.iter().map(|p| p.position.coords).sum::<Vec3>() / n as Real;
    let nearest = points
        .iter()
        .map(|p| {
            let d = p.position.coords - centroid;
            (d - normal * d.dot(normal)).norm()
        })
        .fold(Real::INFINITY, Real::min);
    nearest * (std::f32::consts::PI / n as Real).cos()
}

/// What a constraint holds per manifold rather than per point, built the same way for a
/// scalar constraint ([`prepare_contact`]) and for a lane of a block (`lanes::prepare`), so
/// the two hold the same bits.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ManifoldTerms {
    pub(crate) normal: Vec3,
    pub(crate) tangent1: Vec3,
    pub(crate) tangent2: Vec3,
    pub(crate) dynamic_a: bool,
    pub(crate) dynamic_b: bool,
    pub(crate) inverse_mass_a: Vec3,
    pub(crate) inverse_mass_b: Vec3,
    /// The mixed coefficient (before an effect switch turns friction off).
    pub(crate) friction: Real,
    pub(crate) restitution: Real,
    pub(crate) softness: Softness,
    pub(crate) slop: Real,
    pub(crate) point_count: u32,
    pub(crate) patch_radius: Real,
    pub(crate) tilt_mass: [Real; 2],
    pub(crate) tilt_impulse: [Real; 2],
}

impl ManifoldTerms {
    /// The terms of `contact` between `a` and `b`, whose world inverse inertias are `ja`, `jb`.
    #[inline]
    pub(crate) fn new(
        a: &Body,
        b: &Body,
        ja: &Mat3,
        jb: &Mat3,
        contact: &Contact,
        ctx: &PrepareContext,
    ) -> Self {
        let normal = contact.manifold.normal;
        let (tangent1, tangent2) = tangent_basis(&normal);
        let softness = match ctx.kind {
            SolverKind::SoftStep if a.is_dynamic() && b.is_dynamic() => ctx.contact_softness,
            SolverKind::SoftStep => ctx.static_softness,
            SolverKind::Baumgarte => ctx.contact_softness,
        };
        let patch_radius = patch_radius(contact.manifold.points(), &normal);
        // Tilt rows exist only for a patch (three or more points, a nonzero radius): an
        // impulse carried from an earlier patch onto an edge or a point would act unclamped
        // every substep.
        let tilt_impulse = if patch_radius <= 0.0 {
            [0.0; 2]
        } else {
            [
                ctx.warm_start_scale * contact.tilt_impulse.dot(&tangent1),
                ctx.warm_start_scale * contact.tilt_impulse.dot(&tangent2),
            ]
        };
        let angular = ja + jb;
        let tilt_mass = [&tangent1, &tangent2].map(|t| {
            let k = t.dot(&(angular * t));
            if k > 0.0 { 1.0 / k } else { 0.0 }
        });
        Self {
            normal,
            tangent1,
            tangent2,
            dynamic_a: a.is_dynamic(),
            dynamic_b: b.is_dynamic(),
            inverse_mass_a: a.inverse_mass_axes(),
            inverse_mass_b: b.inverse_mass_axes(),
            friction: crate::mix_friction(a.material.friction, b.material.friction),
            restitution: crate::mix_restitution(a.material.restitution, b.material.restitution),
            softness,
            slop: match ctx.kind {
                SolverKind::Baumgarte => ctx.slop,
                SolverKind::SoftStep => 0.0,
            },
            point_count: u32::from(contact.manifold.len),
            patch_radius,
            tilt_mass,
            tilt_impulse,
        }
    }
}

/// Builds the constraint of `contacts[index]`.
///
/// `inverse_inertia` holds each body's world inverse inertia for this step; `states` gives the
/// velocities used to record the approach speed for restitution.
pub fn prepare_contact(
    bodies: &[Body],
    inverse_inertia: &[Mat3],
    states: &[BodyState],
    contacts: &[Contact],
    index: usize,
    ctx: &PrepareContext,
) -> ContactConstraint {
    let contact = &contacts[index];
    let (ia, ib) = (contact.body_a as usize, contact.body_b as usize);
    let (a, b) = (&bodies[ia], &bodies[ib]);
    let m = ManifoldTerms::new(
        a,
        b,
        &inverse_inertia[ia],
        &inverse_inertia[ib],
        contact,
        ctx,
    );
    let (normal, tangent1, tangent2) = (m.normal, m.tangent1, m.tangent2);
    let mut c = ContactConstraint {
        body_a: contact.body_a,
        body_b: contact.body_b,
        contact: index as u32,
        dynamic_a: m.dynamic_a,
        dynamic_b: m.dynamic_b,
        normal,
        tangent1,
        tangent2,
        inverse_mass_a: m.inverse_mass_a,
        inverse_mass_b: m.inverse_mass_b,
        inverse_inertia_a: inverse_inertia[ia],
        inverse_inertia_b: inverse_inertia[ib],
        friction: m.friction,
        restitution: m.restitution,
        softness: m.softness,
        slop: m.slop,
        point_count: m.point_count,
        points: [ConstraintPoint::default(); MAX_MANIFOLD_POINTS],
        patch_radius: m.patch_radius,
        tilt_mass: m.tilt_mass,
        tilt_push_a: [
            inverse_inertia[ia] * tangent1,
            inverse_inertia[ia] * tangent2,
        ],
        tilt_push_b: [
            inverse_inertia[ib] * tangent1,
            inverse_inertia[ib] * tangent2,
        ],
        tilt_impulse: m.tilt_impulse,
    };
    let (ca, cb) = (a.pose.translation.vector, b.pose.translation.vector);
    let (sa, sb) = (&states[ia], &states[ib]);
    // A frictionless contact has one row per point: its friction rows are never built, and
    // the passes skip them (their impulses stay zero).
    let frictional = c.friction > 0.0;
    for (i, p) in contact.manifold.points().iter().enumerate() {
        let anchor_a = p.position.coords - ca;
        let anchor_b = p.position.coords - cb;
        let warm = &contact.impulses[i];
        let dv = sb.linear_velocity + sb.angular_velocity.cross(&anchor_b)
            - sa.linear_velocity
            - sa.angular_velocity.cross(&anchor_a);
        let (ii_a, ii_b) = (&inverse_inertia[ia], &inverse_inertia[ib]);
        let normal_row = AngularRow::new(ii_a, ii_b, &anchor_a, &anchor_b, &normal);
        let tangent_rows = if frictional {
            [
                AngularRow::new(ii_a, ii_b, &anchor_a, &anchor_b, &tangent1),
                AngularRow::new(ii_a, ii_b, &anchor_a, &anchor_b, &tangent2),
            ]
        } else {
            [AngularRow::default(); 2]
        };
        let normal_mass = row_mass(&c, &normal_row, &normal);
        let normal_impulse = ctx.warm_start_scale * warm.normal;
        c.points[i] = ConstraintPoint {
            anchor_a,
            anchor_b,
            base_separation: -p.depth - (anchor_b - anchor_a).dot(&normal),
            normal_mass,
            tangent_mass: if frictional {
                [
                    row_mass(&c, &tangent_rows[0], &tangent1),
                    row_mass(&c, &tangent_rows[1], &tangent2),
                ]
            } else {
                [0.0; 2]
            },
            normal_impulse,
            tangent_impulse: if frictional {
                [
                    ctx.warm_start_scale * warm.friction.dot(&tangent1),
                    ctx.warm_start_scale * warm.friction.dot(&tangent2),
                ]
            } else {
                [0.0; 2]
            },
            total_normal_impulse: 0.0,
            relative_velocity: dv.dot(&normal),
            normal_row,
            tangent_rows,
        };
    }
    c
}

impl ContactConstraint {
    /// Writes this constraint's final impulses back into its contact.
    pub fn store_impulses(&self, contact: &mut Contact) {
        for (i, p) in self.points[..self.point_count as usize].iter().enumerate() {
            contact.impulses[i].normal = p.normal_impulse;
            contact.impulses[i].friction =
                self.tangent1 * p.tangent_impulse[0] + self.tangent2 * p.tangent_impulse[1];
            contact.total_normal_impulse[i] = p.total_normal_impulse;
        }
        contact.tilt_impulse =
            self.tangent1 * self.tilt_impulse[0] + self.tangent2 * self.tilt_impulse[1];
    }
}
