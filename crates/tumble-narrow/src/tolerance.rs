//! The narrow phase's tolerances, in one place, each with the reason for its value.
//!
//! Separations are compared with a tolerance `rel * |separation| + abs * scale`: the relative part
//! tracks deep penetrations (where a small preference must grow with the depth), the absolute
//! part covers touching contacts, whose separations are all near zero. `scale` is a length of the
//! pair (see [`crate::BoxPair::noise_scale`] and [`crate::BoxPair::feature_scale`]).

use tumble_geometry::Real;

/// Edge pairs whose directions make an angle below `asin(1e-3)` (1 mrad) are skipped: their cross
/// product is shorter than 1e-3, so the `f32` rounding of the rotation (about 1e-7) would tilt the
/// normalised axis by up to 1e-4 rad, and the face axes already cover a contact between (nearly)
/// parallel edges. Compared as a squared length.
pub const PARALLEL_EDGE_SIN_SQ: Real = 1e-6;

/// Box B's face must beat box A's by this fraction of A's separation to become the reference
/// (plus [`FACE_B_ABS_TOL`]): a deterministic preference, so that equal faces (a box resting on an
/// equal box) do not swap on rounding noise.
pub const FACE_B_REL_TOL: Real = 2e-3;

/// Absolute part of the A-over-B face preference, in units of the pair's noise scale (the largest
/// half extent): a few hundred `f32` ulps of the coordinates.
pub const FACE_B_ABS_TOL: Real = 2e-5;

/// An edge axis must beat the best face by this fraction (plus [`EDGE_ABS_TOL`]) to be chosen: a
/// face gives up to four points and a stable manifold, an edge only one, and an edge axis
/// near a face normal ties with that face when a box rests almost flat.
pub const EDGE_REL_TOL: Real = 2e-3;

/// Absolute part of the face-over-edge preference, in units of the noise scale.
pub const EDGE_ABS_TOL: Real = 2e-5;

/// An edge axis within this angle (3 degrees, as a cosine) of the best face's normal is a face
/// contact seen through a slight tilt: a box resting almost flat on an edge of the other (or
/// overhanging it) has its deepest point on an edge crossing, yet the clipped face gives the
/// four points a resting box needs. Such an edge must beat the face by the hysteresis tolerance.
pub const FACE_LIKE_EDGE_COS: Real = 0.998_629_5;

/// The face-like edge rule applies only to contacts shallower than this fraction of the feature
/// scale (5 %): resting and landing contacts, where a one-point edge manifold would rock the
/// box, not deep overlaps, where the deepest axis is what pushes the boxes apart best.
pub const FACE_LIKE_MAX_DEPTH: Real = 0.05;

/// Last step's reference face is kept while its separation stays within this fraction of the
/// best separation (plus [`HYSTERESIS_ABS_TOL`]): a box resting on an equal box sees the two
/// faces trade places on every small tilt, and each swap renames every contact point.
pub const HYSTERESIS_REL_TOL: Real = 0.05;

/// Absolute part of the hysteresis, in units of the pair's feature scale (the smaller box's
/// largest half extent): 1 % of that size covers the separation change of a 0.5 degree tilt
/// (`sin(0.5 deg) = 0.87 %`), the order of jitter a resting stack sees between two steps.
pub const HYSTERESIS_ABS_TOL: Real = 0.01;

/// When the boxes are apart, a contact built on an SAT axis is exact when its closest pair is
/// no farther apart than the separation along that axis plus this (in units of the noise scale):
/// the separation is a lower bound of the distance, equal to it when the axis is the closest
/// pair's direction. Both are computed in A's frame from coordinates of the order of the noise
/// scale, so 2e-6 is about 16 `f32` ulps: rounding, and nothing more, is forgiven.
pub const WITNESS_TOL: Real = 2e-6;

/// `rel * |separation| + abs * scale`: how much better an alternative must be to replace the
/// preferred one.
pub fn tolerance(separation: Real, rel: Real, abs: Real, scale: Real) -> Real {
    rel * separation.abs() + abs * scale
}
