//! Choosing the contact axis among the 15: the deepest one, with preferences that keep the
//! choice stable (A's face over B's, faces over edges, last step's reference face while it
//! stays close enough).

use crate::BoxPair;
use crate::sat::{SatAxis, SatQuery, edge_axis, face_a_separation, face_b_separation};
use crate::tolerance::{
    EDGE_ABS_TOL, EDGE_REL_TOL, FACE_B_ABS_TOL, FACE_B_REL_TOL, FACE_LIKE_EDGE_COS,
    FACE_LIKE_MAX_DEPTH, HYSTERESIS_ABS_TOL, HYSTERESIS_REL_TOL, tolerance,
};
use tumble_geometry::{FeatureKind, Real, Vec3};

/// An axis and its separation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisChoice {
    /// The axis.
    pub axis: SatAxis,
    /// Its separation (negative: overlap).
    pub separation: Real,
}

impl AxisChoice {
    fn new(axis: SatAxis, separation: Real) -> Self {
        Self { axis, separation }
    }
}

/// The axis of largest separation, without preferences (ties: A's faces, then B's, then edges).
pub fn deepest_axis(pair: &BoxPair, sat: &SatQuery) -> AxisChoice {
    let (fa, sa) = sat.best_face_a(pair);
    let (fb, sb) = sat.best_face_b(pair);
    let (e, se) = sat.best_edge();
    let mut choice = AxisChoice::new(SatAxis::FaceA(fa), sa);
    if sb > choice.separation {
        choice = AxisChoice::new(SatAxis::FaceB(fb), sb);
    }
    if se > choice.separation {
        choice = AxisChoice::new(SatAxis::Edge(e), se);
    }
    choice
}

/// The axis to build the contact on: B's face only when it beats A's by more than the face
/// tolerance, an edge only when it beats both faces by more than the edge tolerance (the
/// hysteresis tolerance for an edge axis within 3 degrees of the face normal), and last
/// step's reference face (`previous`, as stored in `Manifold::{kind, feature}`) while its
/// separation stays within the hysteresis tolerance of the best.
pub fn preferred_axis(
    pair: &BoxPair,
    sat: &SatQuery,
    previous: Option<(FeatureKind, u32)>,
) -> AxisChoice {
    let noise = pair.noise_scale();
    let (fa, sa) = sat.best_face_a(pair);
    let (fb, sb) = sat.best_face_b(pair);
    let (e, se) = sat.best_edge();
    let mut choice = AxisChoice::new(SatAxis::FaceA(fa), sa);
    if sb > sa + tolerance(sa, FACE_B_REL_TOL, FACE_B_ABS_TOL, noise) {
        choice = AxisChoice::new(SatAxis::FaceB(fb), sb);
    }
    let best_face = sa.max(sb);
    let edge_slack = edge_slack(
        pair,
        best_face,
        is_face_like(pair, sat, e, choice.axis),
        noise,
    );
    if se > best_face + edge_slack {
        choice = AxisChoice::new(SatAxis::Edge(e), se);
    }

    let kept = match previous {
        Some((FeatureKind::FaceA, f)) if f < 6 => Some(AxisChoice {
            axis: SatAxis::FaceA(f as usize),
            separation: face_a_separation(pair, f as usize),
        }),
        Some((FeatureKind::FaceB, f)) if f < 6 => Some(AxisChoice {
            axis: SatAxis::FaceB(f as usize),
            separation: face_b_separation(pair, f as usize),
        }),
        _ => None,
    };
    if let Some(kept) = kept {
        let best = sat.max_separation();
        let slack = tolerance(
            best,
            HYSTERESIS_REL_TOL,
            HYSTERESIS_ABS_TOL,
            pair.feature_scale(),
        );
        if kept.separation >= best - slack {
            choice = kept;
        }
    }
    choice
}

/// How far the axis [`preferred_axis`] picks without history may trail the deepest one: the
/// largest of the tolerances it applied (A's face over B's, faces over the best edge).
pub fn preference_slack(pair: &BoxPair, sat: &SatQuery) -> Real {
    let noise = pair.noise_scale();
    let (fa, sa) = sat.best_face_a(pair);
    let (fb, sb) = sat.best_face_b(pair);
    let (e, _) = sat.best_edge();
    let best_face = sa.max(sb);
    let face_like = is_face_like(pair, sat, e, SatAxis::FaceA(fa))
        || is_face_like(pair, sat, e, SatAxis::FaceB(fb));
    let edge_slack = edge_slack(pair, best_face, face_like, noise);
    tolerance(sa, FACE_B_REL_TOL, FACE_B_ABS_TOL, noise).max(edge_slack)
}

/// True when edge axis `edge` is within [`FACE_LIKE_EDGE_COS`] of the normal of `face`, and the
/// contact is shallow (see [`FACE_LIKE_MAX_DEPTH`]).
fn is_face_like(pair: &BoxPair, sat: &SatQuery, edge: usize, face: SatAxis) -> bool {
    let face_separation = match face {
        SatAxis::FaceA(f) => face_a_separation(pair, f),
        SatAxis::FaceB(f) => face_b_separation(pair, f),
        SatAxis::Edge(_) => return false,
    };
    if sat.max_separation().min(face_separation) < -FACE_LIKE_MAX_DEPTH * pair.feature_scale() {
        return false;
    }
    let face_normal = match face {
        SatAxis::FaceA(f) => Vec3::ith(f / 2, 1.0),
        SatAxis::FaceB(f) => pair.rot.column(f / 2).into_owned(),
        SatAxis::Edge(_) => return false,
    };
    edge_axis(pair, edge / 3, edge % 3)
        .is_some_and(|n| n.dot(&face_normal).abs() >= FACE_LIKE_EDGE_COS)
}

/// How far an edge axis must beat the best face separation `best_face` to be chosen: the
/// hysteresis tolerance when the edge is `face_like`, the edge tolerance otherwise.
fn edge_slack(pair: &BoxPair, best_face: Real, face_like: bool, noise: Real) -> Real {
    if face_like {
        tolerance(
            best_face,
            HYSTERESIS_REL_TOL,
            HYSTERESIS_ABS_TOL,
            pair.feature_scale(),
        )
    } else {
        tolerance(best_face, EDGE_REL_TOL, EDGE_ABS_TOL, noise)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_geometry::{Cuboid, Pose, Rot, Vec3, nalgebra::Translation3};

    /// Two unit cubes, B resting on A's top face 1 mm deep and tilted by `tilt` radians about z.
    fn resting(tilt: Real) -> BoxPair {
        let cube = Cuboid::new(Vec3::repeat(0.5));
        let rot = Rot::from_euler_angles(0.0, 0.0, tilt);
        // Lowest corner of the tilted cube, relative to its centre.
        let low = (rot * Vec3::new(-0.5, -0.5, 0.0))
            .y
            .min((rot * Vec3::new(0.5, -0.5, 0.0)).y);
        let pose_b = Pose::from_parts(Translation3::new(0.2, 0.5 - 0.001 - low, 0.0), rot);
        BoxPair::new(&cube, &Pose::identity(), &cube, &pose_b)
    }

    #[test]
    fn equal_faces_resolve_to_box_a() {
        let pair = resting(0.0);
        let sat = SatQuery::new(&pair);
        // A's top and B's bottom tie exactly: A's face is the reference, whatever the rounding.
        assert_eq!(preferred_axis(&pair, &sat, None).axis, SatAxis::FaceA(2));
    }

    #[test]
    fn last_steps_face_of_b_is_kept_while_close_and_dropped_when_far() {
        // Tilted 0.3 degrees: faces of A and B differ by a fraction of a millimetre.
        let pair = resting(0.3_f32.to_radians());
        let sat = SatQuery::new(&pair);
        let fresh = preferred_axis(&pair, &sat, None);
        let (fb, _) = sat.best_face_b(&pair);
        let kept = preferred_axis(&pair, &sat, Some((FeatureKind::FaceB, fb as u32)));
        assert_eq!(kept.axis, SatAxis::FaceB(3));
        // Without the history the same pose picks the better face, which is not B's here.
        assert_ne!(fresh.axis, kept.axis);
        // A face of B that looks away from A is never kept, however recent.
        let away = preferred_axis(&pair, &sat, Some((FeatureKind::FaceB, 2)));
        assert_eq!(away.axis, fresh.axis);
    }

    #[test]
    fn the_deepest_axis_has_the_largest_separation() {
        let pair = resting(0.7);
        let sat = SatQuery::new(&pair);
        assert_eq!(deepest_axis(&pair, &sat).separation, sat.max_separation());
    }
}
