//! The ranges of the body and solver quantities the engine accepts, and the checks that
//! refuse a value outside them.
//!
//! Every range is chosen so that the products the solver forms in `f32` (masses and moments
//! of inertia, momenta, squared distances, the soft-contact coefficients) stay finite and
//! normal; `docs/errors.md` gives the arithmetic behind each bound. A check returns an
//! [`InvalidParameter`] naming the field, the value and the range; nothing is clamped.

use tumble_geometry::{Pose, Real, Rot, Vec3};

use crate::{
    Body, BodyKind, BodyState, InvalidParameter, MAX_LINEAR_SPEED, MAX_ROTATION_PER_SUBSTEP,
};

/// Smallest half extent of a box, m (a 2 mm box). Below it the narrow phase's fixed
/// tolerances (about 1e-5 m) and the 2 cm speculative margin dwarf the box itself.
pub const MIN_HALF_EXTENT: Real = 1e-3;
/// Largest half extent of a box, m (a 2 km floor). With [`MAX_DENSITY`] the heaviest box
/// weighs `8e9 m^3 * 1e5 kg/m^3 = 8e14 kg` and its moments `m h^2 / 3` stay below 1e21.
pub const MAX_HALF_EXTENT: Real = 1e3;
/// Smallest density, kg/m^3 (a thousandth of air). With [`MIN_HALF_EXTENT`] the lightest box
/// weighs `8e-9 m^3 * 1e-3 kg/m^3 = 8e-12 kg` and its moments `m h^2 / 3` about 5e-18 kg m^2:
/// normal `f32` numbers whose inverses (2e17) stay far from overflow.
pub const MIN_DENSITY: Real = 1e-3;
/// Largest density, kg/m^3 (four times osmium).
pub const MAX_DENSITY: Real = 1e5;
/// Largest distance of a body's centre (or of an impulse's point, or a kinematic target)
/// from the origin, m: `2^15`. There `f32` positions step by `2^-8 m = 3.9 mm`, still finer
/// than the 5 mm resting overlap the solver tolerates (`DEFAULT_SLOP`); one binade further
/// they step by 7.8 mm and a resting contact's depth can no longer be carried.
pub const MAX_POSITION: Real = 32_768.0;
/// Largest linear speed of a body, m/s: the integrator's own cap, [`MAX_LINEAR_SPEED`], so a
/// velocity the user sets is never shortened silently by the step.
pub const MAX_SPEED: Real = MAX_LINEAR_SPEED;
/// Largest impulse magnitude, N s: the momentum of the heaviest box ([`MAX_HALF_EXTENT`],
/// [`MAX_DENSITY`], 8e14 kg) at [`MAX_SPEED`] is 3.2e17, and its torque about a point
/// [`MAX_POSITION`] away (6.6e22) still leaves 15 decades of `f32` range. The velocities an
/// impulse leaves are checked against [`MAX_SPEED`] and [`max_angular_speed`] as well, so an
/// impulse too strong for a light box is refused too.
pub const MAX_IMPULSE: Real = 1e18;
/// Largest persistent force on a body, N: the heaviest box ([`MAX_HALF_EXTENT`],
/// [`MAX_DENSITY`], 8e14 kg) accelerated at 1.25e5 m/s^2. `force * (inverse_mass * h)` stays
/// far inside `f32`; the velocity a force adds in one step is checked against [`MAX_SPEED`]
/// as well ([`require_force`]), so a force too strong for a light box is refused too.
pub const MAX_FORCE: Real = 1e20;
/// Largest persistent torque on a body, N m: the heaviest box's largest moment
/// (`m h^2 / 3 < 3e20 kg m^2`) turned at 3e3 rad/s^2. As for the force, the spin a torque adds
/// in one step is checked against [`max_angular_speed`] ([`require_torque`]).
pub const MAX_TORQUE: Real = 1e24;
/// Largest magnitude of a body's gravity scale: ten times the world's gravity, up or down.
/// With [`MAX_GRAVITY`] a body then feels at most 1e4 m/s^2, 1e3 m/s per step of [`MAX_DT`],
/// which the integrator's speed cap ([`MAX_SPEED`]) holds to 400 m/s.
pub const MAX_GRAVITY_SCALE: Real = 10.0;
/// Largest gravity magnitude, m/s^2 (about 100 g). At [`MAX_DT`] a step adds 100 m/s, a
/// quarter of [`MAX_SPEED`].
pub const MAX_GRAVITY: Real = 1e3;
/// Shortest step, s (10 kHz). With [`MAX_SUBSTEPS`] the substep is 1.6e-6 s, and the
/// soft-contact rates `1 / h` (6.4e5 1/s) stay well inside `f32`.
pub const MIN_DT: Real = 1e-4;
/// Longest step, s (10 Hz). At [`MAX_SPEED`] a body moves 40 m in one step: the step's AABBs
/// grow by that much, and beyond it the broad phase degenerates to all pairs.
pub const MAX_DT: Real = 0.1;
/// Most substeps per step: every substep runs every solver pass, so this and
/// [`MAX_ITERATIONS`] bound the work of one step (64 * 1024 passes).
pub const MAX_SUBSTEPS: u32 = 64;
/// Most velocity (and relax) passes per substep.
pub const MAX_ITERATIONS: u32 = 1024;
/// Largest linear or angular damping rate, 1/s. The step scales a velocity by
/// `1 / (1 + h c)`; at 1e4 1/s and the default substep (1/360 s) that is 0.035 per substep,
/// a body that stops within one step; larger rates add nothing but a poorly scaled factor.
pub const MAX_DAMPING: Real = 1e4;
/// Largest friction coefficient. Real dry contacts stay below about 2; the contact's
/// coefficient is the geometric mean of its two bodies', so it stays within the range too.
pub const MAX_FRICTION: Real = 10.0;
/// Largest speculative margin, m (the default is 2 cm): a margin above 1 m makes every box
/// within a metre a contact and multiplies the pairs without need.
pub const MAX_MARGIN: Real = 1.0;
/// Largest contact recycle distance, m (the default is 1 mm): a point that slid a centimetre
/// has left the features a fresh manifold would clip, so more would keep stale contacts.
pub const MAX_RECYCLE_DISTANCE: Real = 0.01;
/// Largest contact stiffness, Hz. The soft step caps it at a quarter of the substep rate
/// anyway (at most `0.25 * MAX_SUBSTEPS / MIN_DT = 1.6e5` Hz), so a larger value is never
/// used as given.
pub const MAX_CONTACT_HERTZ: Real = 1e5;
/// Largest contact damping ratio (Box2D's default is 10). `h omega (2 zeta + h omega)` stays
/// below 1e9 for every allowed substep and stiffness.
pub const MAX_DAMPING_RATIO: Real = 1e3;
/// Largest tolerated overlap (slop), m (the default is 5 mm): beyond a tenth of a metre boxes
/// visibly sink into each other.
pub const MAX_SLOP: Real = 0.1;

/// How far a rotation quaternion's norm may be from 1. The engine renormalizes what it is
/// given, so rounding in user data (four or five decimals are off by about 1e-4) is welcome;
/// a quaternion of norm 0 (or 1e-30, whose square underflows) cannot be normalized at all.
pub const MAX_ROTATION_NORM_ERROR: Real = 1e-3;

/// Checks `min <= value <= max` (so a NaN or an infinity is refused too).
pub fn require_in_range(
    field: &'static str,
    value: Real,
    min: Real,
    max: Real,
    expected: &'static str,
) -> Result<Real, InvalidParameter> {
    if value >= min && value <= max {
        Ok(value)
    } else {
        Err(InvalidParameter::new(field, value, expected))
    }
}

/// The Euclidean length of `v`, computed in `f64` so that components near the top of the
/// `f32` range do not overflow the sum of squares.
pub fn length(v: &Vec3) -> f64 {
    v.iter()
        .map(|&c| f64::from(c) * f64::from(c))
        .sum::<f64>()
        .sqrt()
}

/// Checks `0 < value <= max`.
pub fn require_positive_at_most(
    field: &'static str,
    value: Real,
    max: Real,
    expected: &'static str,
) -> Result<Real, InvalidParameter> {
    if value > 0.0 && value <= max {
        Ok(value)
    } else {
        Err(InvalidParameter::new(field, value, expected))
    }
}

/// Checks `min <= value <= max` for a count.
pub fn require_count(
    field: &'static str,
    value: u32,
    min: u32,
    max: u32,
    expected: &'static str,
) -> Result<u32, InvalidParameter> {
    if (min..=max).contains(&value) {
        Ok(value)
    } else {
        Err(InvalidParameter::new(field, value, expected))
    }
}

/// Checks that every component of `v` is finite and its length is at most `max`.
pub fn require_length_at_most(
    field: &'static str,
    v: &Vec3,
    max: Real,
    expected: &'static str,
) -> Result<(), InvalidParameter> {
    // A NaN component makes the length NaN, which fails the comparison.
    if v.iter().all(|c| c.is_finite()) && length(v) <= f64::from(max) {
        Ok(())
    } else {
        Err(InvalidParameter::new(field, [v.x, v.y, v.z], expected))
    }
}

/// The fastest spin the integrator carries unchanged with `substeps` substeps of a `dt` step,
/// rad/s: [`MAX_ROTATION_PER_SUBSTEP`] per substep.
pub fn max_angular_speed(dt: Real, substeps: u32) -> Real {
    MAX_ROTATION_PER_SUBSTEP * substeps as Real / dt
}

/// Checks a position against [`MAX_POSITION`].
pub fn require_position(field: &'static str, p: &Vec3) -> Result<(), InvalidParameter> {
    require_length_at_most(field, p, MAX_POSITION, EXPECTED_POSITION)
}

/// Checks a linear velocity against [`MAX_SPEED`].
pub fn require_linear_speed(field: &'static str, v: &Vec3) -> Result<(), InvalidParameter> {
    require_length_at_most(field, v, MAX_SPEED, EXPECTED_SPEED)
}

/// Checks an angular velocity against [`max_angular_speed`] of `dt` and `substeps`.
pub fn require_angular_speed(
    field: &'static str,
    w: &Vec3,
    dt: Real,
    substeps: u32,
) -> Result<(), InvalidParameter> {
    require_length_at_most(field, w, max_angular_speed(dt, substeps), EXPECTED_ANGULAR)
}

/// The range text of [`MAX_POSITION`].
pub const EXPECTED_POSITION: &str = "finite, at most 32768 m from the origin (MAX_POSITION)";
/// The range text of [`MAX_SPEED`].
pub const EXPECTED_SPEED: &str = "finite, speed at most 400 m/s (MAX_SPEED)";
/// The range text of [`max_angular_speed`].
pub const EXPECTED_ANGULAR: &str =
    "finite, at most MAX_ROTATION_PER_SUBSTEP (pi/4) per substep: pi/4 * substeps / dt rad/s";
/// The range text of a rotation.
pub const EXPECTED_ROTATION: &str =
    "a finite unit quaternion, norm within 1e-3 of 1 (MAX_ROTATION_NORM_ERROR)";
/// The range text of a velocity after a step.
pub const EXPECTED_FINITE: &str = "finite components";
/// The range text of a kinematic target's distance.
pub const EXPECTED_TARGET_SPEED: &str =
    "a pose reachable in one step at most 400 m/s (MAX_SPEED) and within 32768 m of the origin";
/// The range text of a kinematic target's turn.
pub const EXPECTED_TARGET_SPIN: &str =
    "a turn reachable in one step within pi/4 per substep (MAX_ROTATION_PER_SUBSTEP)";
/// The range text of the velocities an impulse leaves.
pub const EXPECTED_IMPULSE_RESULT: &str = "an impulse leaving the body at most 400 m/s \
     (MAX_SPEED) and within pi/4 per substep of spin (MAX_ROTATION_PER_SUBSTEP)";
/// The range text of the half extents.
pub const EXPECTED_HALF_EXTENT: &str =
    "a number in [1e-3, 1e3] m (MIN_HALF_EXTENT..=MAX_HALF_EXTENT)";
/// The range text of the density.
pub const EXPECTED_DENSITY: &str = "a number in [1e-3, 1e5] kg/m^3 (MIN_DENSITY..=MAX_DENSITY)";
/// The range text of the impulse.
pub const EXPECTED_IMPULSE: &str = "finite, magnitude at most 1e18 N s (MAX_IMPULSE)";
/// The range text of the force.
pub const EXPECTED_FORCE: &str = "finite, magnitude at most 1e20 N (MAX_FORCE)";
/// The range text of the torque.
pub const EXPECTED_TORQUE: &str = "finite, magnitude at most 1e24 N m (MAX_TORQUE)";
/// The range text of the velocity change a force leaves in one step.
pub const EXPECTED_FORCE_RESULT: &str = "a force adding at most 400 m/s (MAX_SPEED) to the \
     body's velocity in one step: |force| / mass * dt <= 400";
/// The range text of the spin a torque leaves in one step.
pub const EXPECTED_TORQUE_RESULT: &str = "a torque adding at most pi/4 per substep of spin \
     (MAX_ROTATION_PER_SUBSTEP) in one step: |torque| / (smallest moment) * dt";
/// The range text of the gravity scale.
pub const EXPECTED_GRAVITY_SCALE: &str = "a number in [-10, 10] (MAX_GRAVITY_SCALE)";
/// The range text of gravity.
pub const EXPECTED_GRAVITY: &str = "finite, magnitude at most 1e3 m/s^2 (MAX_GRAVITY)";
/// The range text of the step.
pub const EXPECTED_DT: &str = "a number in [1e-4, 0.1] s (MIN_DT..=MAX_DT)";
/// The range text of the substeps.
pub const EXPECTED_SUBSTEPS: &str = "an integer in [1, 64] (MAX_SUBSTEPS)";
/// The range text of the passes.
pub const EXPECTED_ITERATIONS: &str = "an integer in [1, 1024] (MAX_ITERATIONS)";
/// The range text of the relax passes.
pub const EXPECTED_RELAX_ITERATIONS: &str = "an integer in [0, 1024] (MAX_ITERATIONS)";
/// The range text of the damping rates.
pub const EXPECTED_DAMPING: &str = "a number in [0, 1e4] 1/s (MAX_DAMPING)";
/// The range text of the friction coefficient.
pub const EXPECTED_FRICTION: &str = "a number in [0, 10] (MAX_FRICTION)";
/// The range text of the margin.
pub const EXPECTED_MARGIN: &str = "a number in [0, 1] m (MAX_MARGIN)";
/// The range text of the contact recycle distance.
pub const EXPECTED_RECYCLE_DISTANCE: &str =
    "a number in [0, 0.01] m (MAX_RECYCLE_DISTANCE; 0 turns recycling off)";
/// The range text of the contact stiffness.
pub const EXPECTED_CONTACT_HERTZ: &str = "a number in (0, 1e5] Hz (MAX_CONTACT_HERTZ)";
/// The range text of the damping ratio.
pub const EXPECTED_DAMPING_RATIO: &str = "a number in [0, 1e3] (MAX_DAMPING_RATIO)";
/// The range text of the push-out speed.
pub const EXPECTED_PUSH_OUT: &str = "a number in (0, 400] m/s (MAX_SPEED)";
/// The range text of the restitution threshold.
pub const EXPECTED_RESTITUTION_THRESHOLD: &str = "a number in [0, 400] m/s (MAX_SPEED)";
/// The range text of the slop.
pub const EXPECTED_SLOP: &str = "a number in [0, 0.1] m (MAX_SLOP)";

/// Checks that `q` is finite and of norm within [`MAX_ROTATION_NORM_ERROR`] of 1.
pub fn require_rotation(field: &'static str, q: &Rot) -> Result<(), InvalidParameter> {
    let norm = q
        .coords
        .iter()
        .map(|&c| f64::from(c) * f64::from(c))
        .sum::<f64>()
        .sqrt();
    // A NaN component makes the norm NaN, which fails the comparison.
    if (norm - 1.0).abs() <= f64::from(MAX_ROTATION_NORM_ERROR) {
        Ok(())
    } else {
        let c = q.coords;
        Err(InvalidParameter::new(
            field,
            [c.x, c.y, c.z, c.w],
            EXPECTED_ROTATION,
        ))
    }
}

/// Checks a pose: the centre against [`MAX_POSITION`], the rotation by [`require_rotation`].
pub fn require_pose(field: &'static str, pose: &Pose) -> Result<(), InvalidParameter> {
    require_position(field, &pose.translation.vector)?;
    require_rotation(field, &pose.rotation)
}

/// A quantity of a body's state outside its bounds after a step.
#[derive(Clone, Debug, PartialEq)]
pub struct StateViolation {
    /// `position`, `rotation`, `linear_velocity` or `angular_velocity`.
    pub quantity: &'static str,
    /// The value, formatted.
    pub value: String,
    /// What it must satisfy.
    pub expected: &'static str,
}

/// The first quantity of a moving body at `pose` with velocities `linear` and `angular` that
/// leaves its bounds: a non-finite velocity or rotation, or a centre beyond [`MAX_POSITION`].
/// Speeds are not held to [`MAX_SPEED`] here: contacts solved after the integrator's cap may
/// leave a body slightly faster, and the next step caps it again.
pub fn check_motion(pose: &Pose, linear: &Vec3, angular: &Vec3) -> Option<StateViolation> {
    let violation = |quantity, value: String, expected| {
        Some(StateViolation {
            quantity,
            value,
            expected,
        })
    };
    let p = pose.translation.vector;
    if require_position("position", &p).is_err() {
        return violation(
            "position",
            format!("{:?}", [p.x, p.y, p.z]),
            EXPECTED_POSITION,
        );
    }
    if let Err(e) = require_rotation("rotation", &pose.rotation) {
        return violation("rotation", e.value, EXPECTED_ROTATION);
    }
    for (quantity, v) in [("linear_velocity", linear), ("angular_velocity", angular)] {
        if !v.iter().all(|c| c.is_finite()) {
            return violation(quantity, format!("{:?}", [v.x, v.y, v.z]), EXPECTED_FINITE);
        }
    }
    None
}

/// [`check_motion`] of a body after the solve, before [`crate::finalize_bodies`] writes its
/// deltas into its pose: the pose it would get, and its velocities. Fixed bodies never move
/// and pass.
pub fn check_solved(body: &Body, state: &BodyState) -> Option<StateViolation> {
    if body.kind == BodyKind::Fixed {
        return None;
    }
    let translation = body.pose.translation.vector + state.delta_position;
    // The rotation before `finalize_bodies` normalizes it: a NaN stays NaN, and a unit
    // quaternion times a unit quaternion is unit to round-off.
    let rotation =
        Rot::new_unchecked(state.delta_rotation.into_inner() * body.pose.rotation.into_inner());
    let pose = Pose::from_parts(translation.into(), rotation);
    check_motion(&pose, &state.linear_velocity, &state.angular_velocity)
}

/// Checks the three half extents against [`MIN_HALF_EXTENT`] and [`MAX_HALF_EXTENT`].
pub fn require_half_extents(h: &Vec3) -> Result<(), InvalidParameter> {
    for (field, v) in [
        ("half_extents.x", h.x),
        ("half_extents.y", h.y),
        ("half_extents.z", h.z),
    ] {
        require_in_range(
            field,
            v,
            MIN_HALF_EXTENT,
            MAX_HALF_EXTENT,
            EXPECTED_HALF_EXTENT,
        )?;
    }
    Ok(())
}

/// Checks a density against [`MIN_DENSITY`] and [`MAX_DENSITY`].
pub fn require_density(density: Real) -> Result<(), InvalidParameter> {
    require_in_range(
        "density",
        density,
        MIN_DENSITY,
        MAX_DENSITY,
        EXPECTED_DENSITY,
    )
    .map(|_| ())
}

/// Checks a damping rate against [`MAX_DAMPING`].
pub fn require_damping(field: &'static str, rate: Real) -> Result<(), InvalidParameter> {
    require_in_range(field, rate, 0.0, MAX_DAMPING, EXPECTED_DAMPING).map(|_| ())
}

/// Checks a persistent force for `body` in a world of step `dt`: finite, at most
/// [`MAX_FORCE`], and adding at most [`MAX_SPEED`] to the body's velocity in one step (fixed
/// and kinematic bodies, which a force does not move, take any force up to [`MAX_FORCE`]).
pub fn require_force(body: &Body, force: &Vec3, dt: Real) -> Result<(), InvalidParameter> {
    require_length_at_most("force", force, MAX_FORCE, EXPECTED_FORCE)?;
    let change = length(force) * f64::from(body.inverse_mass) * f64::from(dt);
    if change <= f64::from(MAX_SPEED) {
        Ok(())
    } else {
        Err(InvalidParameter::new(
            "force",
            [force.x, force.y, force.z],
            EXPECTED_FORCE_RESULT,
        ))
    }
}

/// Checks a persistent torque for `body` in a world of step `dt` with `substeps`: finite, at
/// most [`MAX_TORQUE`], and adding at most [`max_angular_speed`] of spin in one step, bounded
/// through the body's largest inverse moment (whatever its rotation).
pub fn require_torque(
    body: &Body,
    torque: &Vec3,
    dt: Real,
    substeps: u32,
) -> Result<(), InvalidParameter> {
    require_length_at_most("torque", torque, MAX_TORQUE, EXPECTED_TORQUE)?;
    let inverse = body.inverse_inertia_local.max();
    let change = length(torque) * f64::from(inverse) * f64::from(dt);
    if change <= f64::from(max_angular_speed(dt, substeps)) {
        Ok(())
    } else {
        Err(InvalidParameter::new(
            "torque",
            [torque.x, torque.y, torque.z],
            EXPECTED_TORQUE_RESULT,
        ))
    }
}

/// Checks a gravity scale against [`MAX_GRAVITY_SCALE`] (zero and negative scales are valid).
pub fn require_gravity_scale(scale: Real) -> Result<(), InvalidParameter> {
    require_in_range(
        "gravity_scale",
        scale,
        -MAX_GRAVITY_SCALE,
        MAX_GRAVITY_SCALE,
        EXPECTED_GRAVITY_SCALE,
    )
    .map(|_| ())
}
