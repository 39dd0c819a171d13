//! One narrow-phase call checked in full: presence, feature choice, normal, SAT separations,
//! the face clip and the deepest depth; and the ids' stability under a tiny perturbation.

use super::*;

/// One call of the narrow phase on `case` with history `previous`, checked in full.
pub(super) fn check_call(
    st: &mut Stats,
    label: &str,
    case: &Case,
    previous: Option<(FeatureKind, u32)>,
) {
    st.calls += 1;
    let (a, b) = case.boxes();
    let (ulp, local_ulp, _) = case.units();
    let band = DECISION_ULPS * local_ulp;
    let spec = Spec::new(&a, &b, MARGIN as f64, band);
    let exact = signed_distance(&a, &b, &spec.sat);
    let (box_a, pose_a, box_b, pose_b) = (&case.a, &case.pose_a, &case.b, &case.pose_b);
    let polygon = contact_polygon(box_a, pose_a, box_b, pose_b, MARGIN, previous);
    let manifold = collide_cuboids_cached(box_a, pose_a, box_b, pose_b, MARGIN, previous);
    let label = format!("{label} prev {previous:?} (exact signed distance {exact:.3e})");
    if manifold != polygon.map(|p| p.to_manifold()) {
        st.fail(format!("{label}: manifold is not the reduced polygon"));
    }
    if previous.is_none() && collide_cuboids(box_a, pose_a, box_b, pose_b, MARGIN) != manifold {
        st.fail(format!("{label}: no history differs from collide_cuboids"));
    }

    let pair = BoxPair::new(box_a, pose_a, box_b, pose_b);
    let sat = SatQuery::new(&pair);
    if previous.is_none() {
        check_sat(st, &label, &pair, &sat, &spec, ulp, local_ulp);
    }

    if (exact - MARGIN as f64).abs() < band {
        st.presence_skipped += 1;
    } else if manifold.is_some() != (exact <= MARGIN as f64) {
        st.fail(format!("{label}: contact {}", manifold.is_some()));
    }
    let got = manifold.map(|m| (m.kind, m.feature));
    match spec.expected(previous) {
        Ok(expected) => {
            st.predicted += 1;
            if got != expected {
                st.fail(format!("{label}: made by {got:?}, expected {expected:?}"));
            }
        }
        Err(why) => *st.ambiguous.entry(why).or_default() += 1,
    }
    match spec.preferred(previous) {
        Ok(axis) => {
            let ours = preferred_axis(&pair, &sat, previous).axis;
            if to_sat_axis(axis) != ours {
                st.fail(format!(
                    "{label}: preferred_axis {ours:?}, expected {axis:?}"
                ));
            }
        }
        Err(why) => *st.ambiguous.entry(why).or_default() += 1,
    }

    let (Some(polygon), Some(m)) = (polygon, manifold) else {
        return;
    };
    st.contacts += 1;
    check_manifold(st, &label, &polygon, &m);
    match m.kind {
        FeatureKind::FaceA | FeatureKind::FaceB => {
            st.made_by[if m.kind == FeatureKind::FaceA { 0 } else { 1 }] += 1;
            st.reduced += usize::from(polygon.len > 4);
            check_face_points(st, &label, &polygon, &a, &b, ulp, band);
            check_face_contact(st, &label, &pair, &polygon, &spec, ulp);
        }
        FeatureKind::Edge => {
            st.made_by[match m.feature {
                f if f < EDGE_PAIR_COUNT => 2,
                f if f < VERTEX_OF_A_FEATURE => 3,
                _ => 4,
            }] += 1;
            check_edge_or_vertex_point(st, &label, &polygon, &a, &b, ulp);
        }
    }

    // Depth: apart, the deepest point is the closest pair (up to the witness tolerance);
    // overlapping, the normal's overlap is the penetration up to the preference tolerances
    // (at most the hysteresis one, the largest).
    let n: V64 = m.normal.cast::<f64>().normalize();
    let along = separation(&a, &b, &n);
    let rounding = POINT_ULPS * ulp;
    if exact > band {
        st.apart += 1;
        let gap = -m.max_depth() as f64;
        let slack = WITNESS_TOL as f64 * spec.noise;
        if gap < exact - rounding || gap > exact + slack + rounding {
            st.fail(format!("{label}: gap {gap}, distance {exact}"));
        }
    } else if exact < -band {
        st.overlapping += 1;
        let largest = HYSTERESIS_REL_TOL as f64 * exact.abs()
            + HYSTERESIS_ABS_TOL as f64 * spec.feature_scale;
        if along < exact - largest - rounding {
            st.fail(format!(
                "{label}: separation along the normal {along}, best {exact}"
            ));
        }
        if previous.is_none() {
            match spec.preference_tolerances() {
                Ok((face_b, edge)) => {
                    // `preference_slack` is the larger of the two, each a product and a sum of
                    // f32 values within a few local ulps of these.
                    let slack = preference_slack(&pair, &sat) as f64;
                    let want = face_b.max(edge);
                    if (slack - want).abs() > 1e-5 * want + local_ulp {
                        st.fail(format!(
                            "{label}: preference slack {slack}, documented {want}"
                        ));
                    }
                    // The face-B tolerance is measured from A's face, the edge one from the
                    // better face: when both apply, the preferred axis trails the deepest by up
                    // to their sum (so by more than `preference_slack`, the larger one alone).
                    if along < exact - (face_b + edge) - rounding {
                        st.fail(format!(
                            "{label}: separation along the normal {along} trails {exact} by \
                             more than the preference tolerances {face_b} + {edge}"
                        ));
                    }
                }
                Err(why) => *st.ambiguous.entry(why).or_default() += 1,
            }
            if along < exact - rounding {
                st.preference_won += 1;
            }
        }
    }
}

pub(super) fn to_sat_axis(axis: Axis) -> SatAxis {
    match axis {
        Axis::FaceA(f) => SatAxis::FaceA(f),
        Axis::FaceB(f) => SatAxis::FaceB(f),
        Axis::Edge(k) => SatAxis::Edge(k),
    }
}

/// Structure shared by every contact: point counts, the reduction keeping a subset of the
/// polygon's points, distinct ids, a unit normal.
pub(super) fn check_manifold(st: &mut Stats, label: &str, polygon: &ContactPolygon, m: &Manifold) {
    if !(1..=4).contains(&m.len) || !(1..=8).contains(&polygon.len) {
        st.fail(format!("{label}: {} points of {}", m.len, polygon.len));
        return;
    }
    let points = polygon.points();
    if m.points().iter().any(|p| !points.contains(p)) {
        st.fail(format!("{label}: a manifold point is not a polygon point"));
    }
    if polygon.len <= 4 && m.points() != points {
        st.fail(format!("{label}: four or fewer points must all be kept"));
    }
    let ids: BTreeSet<u32> = points.iter().map(|p| p.id).collect();
    if ids.len() != points.len() {
        st.fail(format!("{label}: ids repeat: {points:?}"));
    }
    if (m.normal.norm() as f64 - 1.0).abs() > NORMAL_ULPS * Real::EPSILON as f64 {
        st.fail(format!("{label}: normal {:?} not unit", m.normal));
    }
}

/// `face_contact` itself, for the manifold's face: in the reference box's frame, the outward
/// axis normal, the exact incident face, and the exact smallest separation over the clipped
/// polygon (margin or not).
pub(super) fn check_face_contact(
    st: &mut Stats,
    label: &str,
    pair: &BoxPair,
    polygon: &ContactPolygon,
    spec: &Spec,
    ulp: f64,
) {
    let f = polygon.feature as usize;
    let (seen, axis, kind) = if polygon.kind == FeatureKind::FaceA {
        (*pair, Axis::FaceA(f), KIND_FACE_A)
    } else {
        (pair.swapped(), Axis::FaceB(f), KIND_FACE_B)
    };
    let c = face_contact(&seen, f, MARGIN, kind);
    let clip = spec.face_clip(axis);
    if c.normal != Vec3::ith(f / 2, if f.is_multiple_of(2) { 1.0 } else { -1.0 }) {
        st.fail(format!("{label}: face_contact normal {:?}", c.normal));
    }
    if clip.incident_gap > 1e-6 && c.incident_face != clip.incident_face {
        st.fail(format!(
            "{label}: incident face {}, exact {}",
            c.incident_face, clip.incident_face
        ));
    }
    let exact = clip
        .vertices
        .iter()
        .map(|v| -v.depth)
        .fold(f64::INFINITY, f64::min);
    if exact.is_finite() {
        st.bounded(false, (c.min_separation as f64 - exact).abs(), ulp, || {
            format!(
                "{label}: min separation {}, exact {exact}",
                c.min_separation
            )
        });
    } else if c.min_separation != Real::INFINITY {
        st.fail(format!(
            "{label}: empty clip with min separation {}",
            c.min_separation
        ));
    }
}

/// The 15 separations of `SatQuery` against the exact ones (the same axes, each oriented from
/// A to B), and the deepest axis as documented.
pub(super) fn check_sat(
    st: &mut Stats,
    label: &str,
    pair: &BoxPair,
    sat: &SatQuery,
    spec: &Spec,
    ulp: f64,
    local_ulp: f64,
) {
    let exact = &spec.sat;
    let mut compare = |got: Real, want: Option<f64>, unit: f64, what: String| match want {
        Some(w) => {
            let r = (got as f64 - w).abs() / unit;
            st.max_sat_ulps = st.max_sat_ulps.max(r);
            st.max_sat_local = st
                .max_sat_local
                .max((got as f64 - w).abs() / unit * ulp / local_ulp);
            if r.is_nan() || r > POINT_ULPS {
                st.fail(format!("{label}: {what} separation {got}, exact {w}"));
            }
        }
        None => {
            if got != Real::NEG_INFINITY {
                st.fail(format!("{label}: {what} skipped exactly, got {got}"));
            }
        }
    };
    for i in 0..3 {
        compare(
            sat.face_a[i],
            Some(exact.face_a[i]),
            ulp,
            format!("A's axis {i}"),
        );
        compare(
            sat.face_b[i],
            Some(exact.face_b[i]),
            ulp,
            format!("B's axis {i}"),
        );
    }
    for k in 0..9 {
        let sin_sq = exact.edge_sin_sq[k];
        // The squared sine in f32 is off by about 2 sin eps: near the threshold, either way.
        if (sin_sq - crate::tolerance::PARALLEL_EDGE_SIN_SQ as f64).abs() < 1e-8 {
            continue;
        }
        compare(
            sat.edge[k],
            exact.edge[k],
            ulp / sin_sq.sqrt(),
            format!("edge axis {k}"),
        );
    }
    if (sat.max_separation() as f64 - exact.max()).abs() > POINT_ULPS * ulp {
        st.fail(format!("{label}: max separation {}", sat.max_separation()));
    }
    let deepest = deepest_axis(pair, sat);
    if deepest.separation != sat.max_separation() {
        st.fail(format!(
            "{label}: deepest axis {deepest:?} is not the largest separation"
        ));
    }
    if let Ok(axis) = spec.deepest()
        && to_sat_axis(axis) != deepest.axis
    {
        st.fail(format!(
            "{label}: deepest axis {:?}, expected {axis:?}",
            deepest.axis
        ));
    }
}

/// Ids name features, not positions: a perturbation far below any feature's size leaves the
/// polygon's ids as they were, unless the exact clip is that close to changing shape.
pub(super) fn check_perturbed(st: &mut Stats, label: &str, case: &Case, rng: &mut ChaCha8Rng) {
    let (_, _, size) = case.units();
    let step = 1e-5 * size;
    let nudge = Translation3::from(random_rotation(rng) * Vec3::x() * step as Real);
    let turn = Rot::from_axis_angle(&Unit::new_normalize(random_rotation(rng) * Vec3::x()), 1e-5);
    let moved = Case {
        pose_b: Pose::from_parts(
            Translation3::from(case.pose_b.translation.vector + nudge.vector),
            turn * case.pose_b.rotation,
        ),
        ..*case
    };
    let ids = |c: &Case| {
        contact_polygon(&c.a, &c.pose_a, &c.b, &c.pose_b, MARGIN, None).map(|p| {
            let ids: BTreeSet<u32> = p.points().iter().map(|q: &ContactPoint| q.id).collect();
            (p.kind, p.feature, ids)
        })
    };
    let (before, after) = (ids(case), ids(&moved));
    // Far from every decision and clip threshold (1e-3 of the size, a hundred steps), the
    // contact cannot change shape.
    let (a, b) = case.boxes();
    let spec = Spec::new(&a, &b, MARGIN as f64, 1e-3 * size);
    let Ok(Some((kind, feature))) = spec.expected(None) else {
        return;
    };
    if matches!(kind, FeatureKind::FaceA | FeatureKind::FaceB) {
        let axis = if kind == FeatureKind::FaceA {
            Axis::FaceA(feature as usize)
        } else {
            Axis::FaceB(feature as usize)
        };
        let clip = spec.face_clip(axis);
        let settled = clip.incident_gap > 1e-3
            && clip.nearest_plane > 1e-3 * size
            && clip
                .vertices
                .iter()
                .all(|v| (v.depth + MARGIN as f64).abs() > 1e-3 * size);
        if !settled {
            return;
        }
    }
    st.perturbed_compared += 1;
    if before != after {
        st.perturbed_changed += 1;
        st.fail(format!(
            "{label}: ids changed under a 1e-5 perturbation: {before:?} -> {after:?}"
        ));
    }
}
