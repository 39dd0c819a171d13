//! Shared pieces of the builders: the floor and the unit cube.

use tumble_geometry::Real;

use crate::BodySpec;

/// Half extent of the unit cube every stacking scene is made of (a 1 m cube, 1 kg at density 1).
pub const UNIT_HALF: Real = 0.5;
/// Half extents of the default floor: 100 m square, 1 m thick, wide enough for a 50-layer
/// pyramid (about 51 m across) with room to spare.
pub const FLOOR_HALF_EXTENTS: [Real; 3] = [50.0, 0.5, 50.0];
/// Horizontal gap between neighbouring cubes of a layer, in meters. Rapier's pyramid demos
/// leave a gap too: cubes that start exactly side-touching produce side contacts whose
/// friction locks the layer; 5 mm is far below anything visible yet well above f32 round-off
/// at the scene sizes used here (about 4e-6 m at 50 m).
pub const LAYER_GAP: Real = 0.005;

/// The fixed floor: top face at `y = 0`, centred under `(x, z)`.
pub fn floor_at(x: Real, z: Real) -> BodySpec {
    BodySpec::fixed(FLOOR_HALF_EXTENTS, [x, -FLOOR_HALF_EXTENTS[1], z])
}

/// The fixed floor centred under the origin, top face at `y = 0`.
pub fn floor() -> BodySpec {
    floor_at(0.0, 0.0)
}

/// A dynamic unit cube centred at `position`.
pub fn unit_cube(position: [Real; 3]) -> BodySpec {
    BodySpec::dynamic([UNIT_HALF; 3], position)
}
