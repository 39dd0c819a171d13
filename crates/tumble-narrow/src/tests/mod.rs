//! The narrow phase's specification: an exact `f64` reference of box-box contact geometry, the
//! documented feature-choice rules evaluated on it, a seeded random property test over box
//! pairs around touching, and targeted tests of what random pairs do not pin down (exact ties,
//! hysteresis, id packing, tolerance values, frame mapping, the margin cutoff).

mod random_pairs;
mod reference;
mod spec;
mod targeted;

use tumble_geometry::{Cuboid, Manifold, Pose, Real, Rot, Vec3, nalgebra::Translation3};

use crate::{BoxPair, collide_cuboids};

/// The contact margin of the hand-built cases, m.
pub(crate) const MARGIN: Real = 0.02;

/// A cube of half size `h`.
pub(crate) fn cube(h: Real) -> Cuboid {
    Cuboid::new(Vec3::repeat(h))
}

/// The pose at `(x, y, z)` turned by `rot`.
pub(crate) fn at(x: Real, y: Real, z: Real, rot: Rot) -> Pose {
    Pose::from_parts(Translation3::new(x, y, z), rot)
}

/// Two unturned cubes of half size 1, A at the origin and B at `offset`.
pub(crate) fn aligned_pair(offset: Vec3) -> BoxPair {
    BoxPair::new(
        &cube(1.0),
        &Pose::identity(),
        &cube(1.0),
        &Pose::translation(offset.x, offset.y, offset.z),
    )
}

/// A cube of half size 0.5 centred at `(x, y, z)`, unturned, against a 10 x 1 x 10 slab (A)
/// centred at the origin (its top face at y = 0.5).
pub(crate) fn cube_on_slab(x: Real, y: Real, z: Real) -> Option<Manifold> {
    let slab = Cuboid::new(Vec3::new(5.0, 0.5, 5.0));
    let pose = Pose::translation(x, y, z);
    collide_cuboids(&slab, &Pose::identity(), &cube(0.5), &pose, MARGIN)
}

/// Two cubes of half size `half`: A turned 45 degrees about z, B turned 45 degrees about x and
/// raised so that A's top edge (along z) and B's bottom edge (along x) cross `gap` apart
/// (negative: overlapping) above the origin.
pub(crate) fn crossed_edges(half: Real, gap: Real) -> (Pose, Pose) {
    let q = std::f32::consts::FRAC_PI_4;
    (
        at(0.0, 0.0, 0.0, Rot::from_euler_angles(0.0, 0.0, q)),
        at(
            0.0,
            2.0 * half * 2f32.sqrt() + gap,
            0.0,
            Rot::from_euler_angles(q, 0.0, 0.0),
        ),
    )
}
