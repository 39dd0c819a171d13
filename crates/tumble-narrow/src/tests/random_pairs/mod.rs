//! A seeded random property test: box pairs of random sizes and rotations, placed around
//! touching, each manifold checked against the exact `f64` reference of `reference.rs` and the
//! documented feature choice of `spec.rs`.
//!
//! Every pair is tested both ways round and with four histories (none, last step's face on A,
//! on B, and a random face), and once more slightly perturbed to check that ids stay the same.
//! What must hold, per call:
//! - presence: a manifold exactly when the exact signed distance is within the margin;
//! - `kind` and `feature` as the documented rules pick them (and `preferred_axis`,
//!   `deepest_axis` as documented); every SAT separation equals the exact one;
//! - 1 to 4 points, all among the unreduced polygon's (which holds 1 to 8), ids distinct;
//! - the normal: unit, and the exact direction of the feature pair that made it;
//! - every point against the exact geometry of its features (see `check_face_points`,
//!   `check_edge_or_vertex_point`), its id decoded by the documented bit layout;
//! - a face contact's points are exactly the exact clipped polygon's vertices within the margin;
//! - the deepest depth: minus the distance when apart (up to the witness tolerance), and never
//!   worse than the penetration by more than the preference tolerances when overlapping.
//!
//! The units of every threshold: `ulp` is `f32::EPSILON` times the magnitude of the coordinates
//! (the larger box's size plus both centres' distances from the origin). The inputs widen to
//! `f64` exactly, so every error is the `f32` pipeline's rounding: a few ulps per transform, clip
//! or projection. A wrong sign, index, feature or formula is off by a fraction of a box's size,
//! which is thousands of ulps at the least.

mod calls;
mod cases;
mod points;

use calls::*;
use cases::*;
use points::*;

use super::reference::{
    Box64, FaceClip, V64, clip_face, segment_closest, separation, side_plane, signed_distance,
};
use super::spec::{Axis, Spec};
use crate::feature_id::{KIND_EDGE, KIND_FACE_A, KIND_FACE_B, KIND_VERTEX, id_kind};
use crate::tolerance::{HYSTERESIS_ABS_TOL, HYSTERESIS_REL_TOL, WITNESS_TOL};
use crate::{
    BoxPair, ContactPolygon, EDGE_PAIR_COUNT, SatAxis, SatQuery, VERTEX_OF_A_FEATURE,
    collide_cuboids, collide_cuboids_cached, contact_polygon, deepest_axis, face_contact,
    preference_slack, preferred_axis,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::{BTreeMap, BTreeSet};
use tumble_geometry::{
    CUBOID_FACES, ContactPoint, Cuboid, FeatureKind, Manifold, Pose, Real, Rot, Vec3,
    nalgebra::{Quaternion, Translation3, Unit},
};

/// A typical speculative margin.
const MARGIN: Real = 0.02;
/// Random pairs of each of the three families (each tested both ways round).
const PAIRS: usize = 1000;
/// Point positions, depths and witnesses: within this many ulps of the exact geometry. The
/// largest error seen over this seed is about 3 ulps (the frame change, the clip interpolation
/// and the transform back to world space); 32 leaves room for a reordering of that arithmetic
/// and nothing more.
const POINT_ULPS: f64 = 32.0;
/// Unit normals: within this many `f32::EPSILON` of the exact direction (a face normal is one
/// rotation of a unit vector; an edge or vertex normal is scaled by its conditioning, see the
/// units in the checks). Largest seen: about 7.
const NORMAL_ULPS: f64 = 16.0;
/// Decisions (which side of a threshold an exact value lies), in local ulps (`f32::EPSILON`
/// times the pair's size plus its centres' distance: the magnitude of the coordinates in A's
/// frame, where the narrow phase computes): within this band of a threshold either side is
/// right. The narrow phase documents its witness tolerance (about 8 such units) as covering its
/// rounding, so its decisions are meant to be right outside a band well below that; half of
/// it is used. The SAT separations themselves are within 5 local ulps of the exact ones.
const DECISION_ULPS: f64 = 4.0;

#[derive(Clone, Copy, Debug)]
struct Case {
    a: Cuboid,
    pose_a: Pose,
    b: Cuboid,
    pose_b: Pose,
}

impl Case {
    fn swapped(&self) -> Self {
        Self {
            a: self.b,
            pose_a: self.pose_b,
            b: self.a,
            pose_b: self.pose_a,
        }
    }

    fn boxes(&self) -> (Box64, Box64) {
        (
            Box64::new(&self.a, &self.pose_a),
            Box64::new(&self.b, &self.pose_b),
        )
    }

    /// (ulp, local ulp, size): see the module docs.
    fn units(&self) -> (f64, f64, f64) {
        let size = 2.0 * self.a.half_extents.max().max(self.b.half_extents.max()) as f64;
        let coordinates = size
            + self.pose_a.translation.vector.norm() as f64
            + self.pose_b.translation.vector.norm() as f64;
        let delta = (self.pose_b.translation.vector - self.pose_a.translation.vector).norm() as f64;
        let eps = Real::EPSILON as f64;
        (eps * coordinates, eps * (size + delta), size)
    }
}

#[derive(Default, Debug)]
struct Stats {
    calls: usize,
    contacts: usize,
    presence_skipped: usize,
    predicted: usize,
    ambiguous: BTreeMap<&'static str, usize>,
    /// Manifolds by what made them: face of A, face of B, edge pair, vertex of B, vertex of A.
    made_by: [usize; 5],
    overlapping: usize,
    apart: usize,
    /// Face contacts with more than four clipped points (the reduction ran).
    reduced: usize,
    /// Calls whose history kept a face that the same pose without history does not pick.
    kept_by_history: usize,
    /// Calls whose history named a face that was not kept.
    dropped_history: usize,
    /// Manifolds whose normal trails the deepest axis by more than rounding (a preference won).
    preference_won: usize,
    polygon_counts_compared: usize,
    perturbed_compared: usize,
    perturbed_changed: usize,
    max_point_ulps: f64,
    max_normal_ulps: f64,
    max_sat_ulps: f64,
    max_sat_local: f64,
    failures: Vec<String>,
}

impl Stats {
    fn fail(&mut self, what: String) {
        if self.failures.len() < 20 {
            self.failures.push(what);
        }
    }

    /// Records `error / unit` and fails when it exceeds `bound` (or is NaN).
    fn bounded(&mut self, normal: bool, error: f64, unit: f64, what: impl FnOnce() -> String) {
        let ratio = error / unit;
        let (max, bound) = if normal {
            (&mut self.max_normal_ulps, NORMAL_ULPS)
        } else {
            (&mut self.max_point_ulps, POINT_ULPS)
        };
        *max = max.max(ratio);
        if ratio.is_nan() || ratio > bound {
            let what = what();
            self.fail(format!("{what}: {ratio:.1} units > {bound}"));
        }
    }
}

/// Exactly, whether the boxes overlap: no separating axis among the 15 (all edge pairs but
/// exactly parallel ones, which the face axes cover).

#[test]
fn random_pairs_match_the_exact_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_b0c5);
    let mut st = Stats::default();
    for i in 0..3 * PAIRS {
        let case = match i % 3 {
            0 => random_case(&mut rng),
            1 => stacked_case(&mut rng),
            _ => corner_case(&mut rng),
        };
        for (which, c) in [("", case), (" swapped", case.swapped())] {
            let label = format!("pair {i}{which}");
            let (a, b) = c.boxes();
            let spec = Spec::new(&a, &b, MARGIN as f64, 0.0);
            let fa = spec.face_a_facing(super::reference::best_of(&spec.sat.face_a).0) as u32;
            let fb = spec.face_b_facing(super::reference::best_of(&spec.sat.face_b).0) as u32;
            let random = (
                if rng.random_bool(0.5) {
                    FeatureKind::FaceA
                } else {
                    FeatureKind::FaceB
                },
                rng.random_range(0..6),
            );
            let fresh = collide_cuboids(&c.a, &c.pose_a, &c.b, &c.pose_b, MARGIN);
            for previous in [
                None,
                Some((FeatureKind::FaceA, fa)),
                Some((FeatureKind::FaceB, fb)),
                Some(random),
            ] {
                check_call(&mut st, &label, &c, previous);
                if let (Some(p), Some(m)) = (previous, fresh) {
                    let kept =
                        collide_cuboids_cached(&c.a, &c.pose_a, &c.b, &c.pose_b, MARGIN, previous)
                            .map(|k| (k.kind, k.feature));
                    if kept == Some(p) && (m.kind, m.feature) != p {
                        st.kept_by_history += 1;
                    } else if kept != Some(p) {
                        st.dropped_history += 1;
                    }
                }
            }
            check_perturbed(&mut st, &label, &c, &mut rng);
        }
    }
    println!("{st:#?}");
    assert!(
        st.failures.is_empty(),
        "{} failures:\n{}",
        st.failures.len(),
        st.failures.join("\n")
    );
    let calls = st.calls;
    // Coverage: every branch the checks depend on ran, many times over (bounds at about half
    // of what this seed gives, see the printout), and the predictions skipped near thresholds
    // stay rare (this seed: 0.7 % of the calls, and no presence check).
    assert!(
        st.predicted >= calls * 98 / 100,
        "{} of {calls} predicted",
        st.predicted
    );
    assert!(st.presence_skipped <= calls / 200);
    for (count, at_least, what) in [
        (st.made_by[0], 4000, "face A contacts"),
        (st.made_by[1], 4000, "face B contacts"),
        (st.made_by[2], 2400, "edge contacts"),
        (st.made_by[3], 50, "vertex of B contacts"),
        (st.made_by[4], 50, "vertex of A contacts"),
        (st.overlapping, 7000, "overlapping contacts"),
        (st.apart, 3000, "apart contacts"),
        (st.reduced, 200, "reduced face polygons"),
        (st.kept_by_history, 250, "faces kept by history"),
        (st.dropped_history, 5000, "histories dropped"),
        (st.preference_won, 90, "preferences over the deepest axis"),
        (
            st.polygon_counts_compared,
            8000,
            "clipped polygons compared",
        ),
        (st.perturbed_compared, 700, "perturbations compared"),
    ] {
        assert!(
            count >= at_least,
            "{count} {what}, expected at least {at_least}"
        );
    }
}
