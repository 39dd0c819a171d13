//! The solver's specification: closed-form cases (a box resting, sliding, bouncing, two boxes
//! colliding), an f64 reference of the sequential-impulse kernels derived from their documented
//! formulas, and the contracts of coloring, integration, mass properties, the contact cache,
//! islands and sleep.

mod bounds;
mod cache;
mod coloring;
mod integration;
mod islands;
mod kernels;
mod lanes;
mod mass;
mod misc;
mod prepare;
mod recycle;
mod reference;
mod scenes;
mod serial_stages;
mod solve_stage;
mod tilt;

use tumble_geometry::{ContactPoint, Cuboid, FeatureKind, Manifold, Point3, Pose, Real, Vec3};

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::{
    Body, BodyKind, BodyState, Coloring, Contact, Effects, Material, SolveStats, SolverConfig,
    color_contacts, finalize_bodies, solve, solve_with_effects,
};

/// Standard gravity, m/s^2.
pub(crate) const G: Real = 9.81;

/// The engine's default step, s.
pub(crate) const DT: Real = 1.0 / 60.0;

/// Downward gravity.
pub(crate) fn gravity() -> Vec3 {
    Vec3::new(0.0, -G, 0.0)
}

/// A body of `kind` with half extents `half` at `pose`, density `density`.
pub(crate) fn body(
    kind: BodyKind,
    half: Vec3,
    pose: Pose,
    density: Real,
    material: Material,
) -> Body {
    Body::new(kind, Cuboid::new(half), pose, density, material).unwrap()
}

/// A material of friction `friction` and restitution `restitution`.
pub(crate) fn material(friction: Real, restitution: Real) -> Material {
    Material {
        friction,
        restitution,
    }
}

/// A fixed floor whose top face is the plane y = 0.
pub(crate) fn floor(material: Material) -> Body {
    body(
        BodyKind::Fixed,
        Vec3::new(5.0, 0.5, 5.0),
        Pose::translation(0.0, -0.5, 0.0),
        1.0,
        material,
    )
}

/// A unit cube of `kind` and density 1 at `pose`.
pub(crate) fn cube(kind: BodyKind, pose: Pose, material: Material) -> Body {
    body(kind, Vec3::repeat(0.5), pose, 1.0, material)
}

/// A dynamic unit cube of mass `mass` (density = mass, volume 1) at `pose`.
pub(crate) fn unit_cube(mass: Real, pose: Pose, material: Material) -> Body {
    body(BodyKind::Dynamic, Vec3::repeat(0.5), pose, mass, material)
}

/// A manifold of normal `normal` from `(position, depth, id)` triples.
pub(crate) fn manifold(normal: Vec3, points: &[(Point3, Real, u32)]) -> Manifold {
    let mut m = Manifold {
        normal,
        kind: FeatureKind::FaceA,
        feature: 2,
        ..Default::default()
    };
    for &(position, depth, id) in points {
        assert!(m.push(ContactPoint {
            position,
            depth,
            id,
        }));
    }
    m
}

/// The floor contact of an upright box: its four bottom corners against the plane y = 0, each
/// point midway between the corner and the plane (an exact narrow phase for an upright box).
pub(crate) fn floor_corners(b: &Body) -> Manifold {
    let points: Vec<(Point3, Real, u32)> = [0usize, 1, 4, 5]
        .into_iter()
        .enumerate()
        .map(|(id, v)| {
            let c = b.pose * b.shape.vertex(v);
            (Point3::new(c.x, 0.5 * c.y, c.z), -c.y, id as u32)
        })
        .collect();
    manifold(Vec3::y(), &points)
}

/// The floor contact of a box as one point straight below its centre: the arm is parallel to
/// the normal, so the normal row has no angular part and the contact is one-dimensional.
pub(crate) fn floor_center(b: &Body) -> Manifold {
    let c = b.pose.translation.vector;
    let bottom = c.y - b.shape.half_extents.y;
    manifold(
        Vec3::y(),
        &[(Point3::new(c.x, 0.5 * bottom, c.z), -bottom, 0)],
    )
}

/// One step of `contacts` over `bodies`, colored greedily, then the poses are written.
pub(crate) fn step(
    bodies: &mut [Body],
    states: &mut [BodyState],
    contacts: &mut [Contact],
    config: &SolverConfig,
    gravity: &Vec3,
    effects: &Effects,
) -> SolveStats {
    let coloring = color_contacts(contacts, bodies);
    let stats = solve_with_effects(
        bodies, states, contacts, &coloring, config, DT, gravity, effects,
    );
    finalize_bodies(bodies, states);
    stats
}

/// One solve of the default step [`DT`] on copies of `states` and `contacts` (the poses are not
/// written): the states, contacts and statistics after it.
pub(crate) fn solve_copy(
    bodies: &[Body],
    states: &[BodyState],
    contacts: &[Contact],
    coloring: &Coloring,
    config: &SolverConfig,
    gravity: &Vec3,
) -> (Vec<BodyState>, Vec<Contact>, SolveStats) {
    let (mut states, mut contacts) = (states.to_vec(), contacts.to_vec());
    let stats = solve(
        bodies,
        &mut states,
        &mut contacts,
        coloring,
        config,
        DT,
        gravity,
    );
    (states, contacts, stats)
}

/// `|a - b| <= tol`, with a message naming the quantity.
#[track_caller]
pub(crate) fn assert_close(what: &str, got: f64, expected: f64, tol: f64) {
    assert!(
        (got - expected).abs() <= tol,
        "{what}: got {got}, expected {expected} (tolerance {tol})"
    );
}

/// [`assert_close`] on each component of a vector.
#[track_caller]
pub(crate) fn assert_close3(what: &str, got: &Vec3, expected: &reference::V, tol: f64) {
    for j in 0..3 {
        assert_close(what, got[j].into(), expected[j], tol);
    }
}

/// A uniformly random unit direction (a normalised point of the cube, away from its centre).
pub(crate) fn unit(rng: &mut ChaCha8Rng) -> Vec3 {
    loop {
        let v = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if v.norm() > 0.1 {
            return v.normalize();
        }
    }
}
