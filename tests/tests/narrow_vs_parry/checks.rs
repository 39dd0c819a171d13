//! The checks of one pair: presence, normal and depth against parry and the exact answer,
//! and every point against the exact geometry of its features.

use super::*;

/// Records `error / unit` in `max` and fails when it exceeds `bound` (or is NaN).
pub(super) fn bounded(
    max: &mut f64,
    error: f64,
    unit: f64,
    bound: f64,
    fail: &mut impl FnMut(String),
    what: impl FnOnce() -> String,
) {
    let ratio = error / unit;
    *max = max.max(ratio);
    // Not `ratio <= bound` fails, NaN included.
    if !matches!(
        ratio.partial_cmp(&bound),
        Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal)
    ) {
        fail(format!("{} ({ratio:.1} > {bound} units)", what()));
    }
}

/// How far `s` lies outside `[lo, hi]`.
pub(super) fn outside(s: f64, lo: f64, hi: f64) -> f64 {
    (lo - s).max(s - hi).max(0.0)
}

/// Checks every point of `m` against the exact f64 geometry of the feature pair that made it.
///
/// A point `p` with depth `d` claims to be midway between a point of A's surface, `p + n d / 2`,
/// and a point of B's, `p - n d / 2` (`n` from A to B, `d > 0` overlapping), so both are checked
/// with signed distances, which see how deep a point is (an unsigned one is 0 anywhere inside).
/// On top of that, per kind:
/// - face contact: the normal is the reference face's outward normal (its opposite for B's face);
///   the witness on the reference box lies in that face; `d` is the exact height of the incident
///   witness below the face's plane; and that witness is where a point `d` below the face, within
///   its side planes, must be: inside the reference box (signed distance in
///   `[-min(d, t - d), 0]`, `t` the box's thickness along the normal) when `0 < d <= t`, exactly
///   `d - t` beyond its far face when `d > t` (the incident box sticks out on both sides), and
///   exactly `-d` above the face when apart;
/// - edge contact: the normal is the exact cross product of the two edge directions, `d` the
///   boxes' exact overlap along it (the support edges are their extreme points there), `p` the
///   midpoint of the two edges' exact closest points; apart, those points are no farther apart
///   than `-d` plus the witness tolerance (the rule that accepts an edge axis), and each is
///   exactly `-d` from the other box;
/// - vertex contact (apart only): the normal is the exact direction from the vertex to the
///   nearest point of the other box (or back), `-d` their exact distance, `p` their midpoint,
///   and each witness is exactly `-d` from the other box.
pub(super) fn check_points(
    m: &tumble_geometry::Manifold,
    a: &Box64,
    b: &Box64,
    ulp: f64,
    st: &mut PointStats,
    fail: &mut impl FnMut(String),
) {
    let n: V64 = m.normal.cast();
    let eps = Real::EPSILON as f64;
    let size = 2.0 * a.half.iter().chain(&b.half).fold(0.0f64, |x, &h| x.max(h));
    for c in m.points() {
        if c.depth > 0.0 {
            st.penetrating += 1;
        } else {
            st.apart += 1;
        }
    }
    let points = || {
        m.points()
            .iter()
            .map(|c| (c.position.coords.cast::<f64>(), c.depth as f64))
    };
    if matches!(m.kind, FeatureKind::FaceA | FeatureKind::FaceB) {
        let (reference, incident, towards) = if m.kind == FeatureKind::FaceA {
            (a, b, 1.0)
        } else {
            (b, a, -1.0)
        };
        let f = m.feature as usize;
        let (face_n, offset) = reference.face_plane(f);
        let thickness = 2.0 * reference.half[f / 2];
        bounded(
            &mut st.max_normal_ulps,
            (n * towards - face_n).norm(),
            eps,
            NORMAL_ULPS,
            fail,
            || format!("{:?} normal {n:?} is not face {f}'s {face_n:?}", m.kind),
        );
        for (p, d) in points() {
            st.face += 1;
            let on_reference = p + face_n * (0.5 * d);
            let witness = p - face_n * (0.5 * d);
            let what = |q: &str| format!("{:?} point {p:?} depth {d}: {q}", m.kind);
            let height = offset - face_n.dot(&witness);
            bounded(
                &mut st.max_depth_ulps,
                (d - height).abs(),
                ulp,
                POINT_ULPS,
                fail,
                || what(&format!("the incident witness is {height} below the face")),
            );
            let surface = reference
                .signed_distance(&on_reference)
                .abs()
                .max(incident.signed_distance(&witness).abs());
            bounded(
                &mut st.max_surface_ulps,
                surface,
                ulp,
                POINT_ULPS,
                fail,
                || what("a witness is off the reference face or the incident surface"),
            );
            // The witness's coordinate along the face normal, from the reference box's centre.
            let z = 0.5 * thickness - d;
            let (lo, hi) = if z.abs() <= 0.5 * thickness {
                (z.abs() - 0.5 * thickness, 0.0)
            } else {
                (z.abs() - 0.5 * thickness, z.abs() - 0.5 * thickness)
            };
            if d > 0.0 && d <= thickness {
                st.face_inside += 1;
            }
            let s = reference.signed_distance(&witness);
            bounded(
                &mut st.max_inside_ulps,
                outside(s, lo, hi),
                ulp,
                POINT_ULPS,
                fail,
                || {
                    what(&format!(
                        "incident witness is {s} from the reference box, not in [{lo}, {hi}]"
                    ))
                },
            );
        }
        return;
    }
    // The exact pair of points an edge or vertex contact claims, its exact normal, and the units
    // of the normal's and the position's errors: the closest points of two lines crossing at an
    // angle move along them by the inputs' rounding over the sine of that angle.
    let (on_a, on_b, exact_n, normal_unit, position_unit, what) = if m.feature < EDGE_PAIR_COUNT {
        st.edge += m.len as usize;
        let (ea, eb) = ((m.feature / 12) as usize, (m.feature % 12) as usize);
        let axis = a.axes[ea / 4].cross(&b.axes[eb / 4]);
        let sin = axis.norm();
        let mut exact_n = axis / sin;
        if exact_n.dot(&(b.centre - a.centre)) < 0.0 {
            exact_n = -exact_n;
        }
        let [a0, a1] = CUBOID_EDGES[ea];
        let [b0, b1] = CUBOID_EDGES[eb];
        let (on_a, on_b) =
            segment_closest64(a.vertex(a0), a.vertex(a1), b.vertex(b0), b.vertex(b1));
        let what = format!("edges {ea}, {eb}");
        (on_a, on_b, exact_n, eps / sin, ulp / sin, what)
    } else {
        st.vertex += m.len as usize;
        let (on_a, on_b, what) = if m.feature < VERTEX_OF_A_FEATURE {
            let v = (m.feature - EDGE_PAIR_COUNT) as usize;
            let on_b = b.vertex(v);
            (a.closest_point(&on_b), on_b, format!("B's vertex {v}"))
        } else {
            let v = (m.feature - VERTEX_OF_A_FEATURE) as usize;
            let on_a = a.vertex(v);
            (on_a, b.closest_point(&on_a), format!("A's vertex {v}"))
        };
        let gap = on_b - on_a;
        (on_a, on_b, gap / gap.norm(), ulp / gap.norm(), ulp, what)
    };
    bounded(
        &mut st.max_normal_ulps,
        (n - exact_n).norm(),
        normal_unit,
        NORMAL_ULPS,
        fail,
        || format!("{what}: normal {n:?}, exact {exact_n:?}"),
    );
    let gap = on_a - on_b;
    // A clamped edge end leaves part of the gap across the normal: the midpoint shifted by half
    // the depth along the normal then misses each surface by up to half of that part.
    let across = (gap - exact_n * gap.dot(&exact_n)).norm();
    let exact_d = if m.feature < EDGE_PAIR_COUNT {
        -separation64(a, b, &exact_n)
    } else {
        -gap.norm()
    };
    let slot = usize::from(exact_d <= 0.0);
    st.max_edge_across[slot] = st.max_edge_across[slot].max(across / size);
    for (p, d) in points() {
        let what = |q: &str| format!("{what}: point {p:?} depth {d}: {q}");
        bounded(
            &mut st.max_depth_ulps,
            (d - exact_d).abs(),
            ulp,
            POINT_ULPS,
            fail,
            || what(&format!("exact depth {exact_d}")),
        );
        let midpoint = 0.5 * (on_a + on_b);
        bounded(
            &mut st.max_position_ulps,
            (p - midpoint).norm(),
            position_unit,
            POINT_ULPS,
            fail,
            || what(&format!("exact midpoint {midpoint:?}")),
        );
        let (wa, wb) = (p + n * (0.5 * d), p - n * (0.5 * d));
        bounded(
            &mut st.max_surface_ulps,
            (a.signed_distance(&wa)
                .abs()
                .max(b.signed_distance(&wb).abs())
                - 0.5 * across)
                .max(0.0),
            ulp,
            POINT_ULPS,
            fail,
            || what("a witness is off its surface"),
        );
        if d <= 0.0 {
            // Apart: the closest pair, as the edge axis was accepted for it (its points no
            // farther apart than the separation plus the witness tolerance), each point
            // exactly `-d` from the other box.
            let slack = WITNESS_TOL as f64 * 0.5 * size;
            bounded(
                &mut st.max_inside_ulps,
                outside(gap.norm(), -d, -d + slack),
                ulp,
                POINT_ULPS,
                fail,
                || {
                    what(&format!(
                        "the exact closest points are {} apart",
                        gap.norm()
                    ))
                },
            );
            let (sa, sb) = (a.signed_distance(&on_b), b.signed_distance(&on_a));
            bounded(
                &mut st.max_inside_ulps,
                outside(sa, -d, -d + slack).max(outside(sb, -d, -d + slack)),
                ulp,
                POINT_ULPS,
                fail,
                || what(&format!("the witnesses are {sa} from A and {sb} from B")),
            );
        }
    }
}

/// Checks one pair against parry (and against the exact answer where parry misses it).
pub(super) fn check(
    stats: &mut Stats,
    label: &str,
    a: &Cuboid,
    pose_a: &Pose,
    b: &Cuboid,
    pose_b: &Pose,
) {
    stats.pairs += 1;
    let size = 2.0 * a.half_extents.max().max(b.half_extents.max()) as f64;
    let band = SIZE_FRACTION as f64 * size;
    // What f32 rounding alone can move a separation by: a few ulps of the largest coordinate.
    let coordinates =
        size + pose_a.translation.vector.norm() as f64 + pose_b.translation.vector.norm() as f64;
    let rounding = 8.0 * Real::EPSILON as f64 * coordinates;
    let (a64, b64) = (Box64::new(a, pose_a), Box64::new(b, pose_b));
    let exact = exact_signed_distance(&a64, &b64);
    match exact {
        s if s <= 0.0 => stats.overlapping += 1,
        s if s <= MARGIN as f64 => stats.within_margin += 1,
        _ => stats.apart += 1,
    }
    let ours = collide_cuboids(a, pose_a, b, pose_b, MARGIN);
    let mut fail = |what: String| {
        stats.failures.push(format!(
            "{label}: {what}\n  a {:?} at {:?}\n  b {:?} at {:?}",
            a.half_extents, pose_a, b.half_extents, pose_b
        ))
    };

    // The reference: parry, unless it gave up or is farther than half the band from the exact
    // answer (its GJK stops when its bounds are within 1e-3 of each other, relative): then the
    // exact one. Half, so that parry's own error leaves room for ours within the band.
    let parry_full = parry_contact(a, pose_a, b, pose_b, 1e6);
    let reference = match parry_full {
        None => {
            stats.parry_gave_up += 1;
            exact
        }
        Some((d, _)) if (d as f64 - exact).abs() > 0.5 * band => {
            stats.parry_off_exact += 1;
            exact
        }
        Some((d, _)) => d as f64,
    };
    let ambiguous = reference.abs() < band || (reference - MARGIN as f64).abs() < band;
    if ambiguous {
        stats.presence_skipped += 1;
    } else {
        stats.presence_checked += 1;
        let expected = reference <= MARGIN as f64;
        if ours.is_some() != expected {
            fail(format!(
                "presence: ours {} expected {expected} (reference signed distance {reference}, exact {exact})",
                ours.is_some()
            ));
        }
    }
    let Some(m) = ours else { return };
    stats.both_contact += 1;

    // Normal: parry's within 1e-3 rad; otherwise ours must be at least as good a direction (score:
    // the exact separation along it, whose maximum over directions is the signed distance), or
    // within our preference tolerance of the best axis (a tie: an exemption, counted).
    let n = m.normal;
    if (n.norm() - 1.0).abs() > 1e-5 {
        fail(format!("normal not unit: {n:?}"));
    }
    let n64: V64 = n.cast::<f64>().normalize();
    let ours_sep = separation64(&a64, &b64, &n64);
    let mut exempt = false;
    if let Some((_, pn)) = parry_full {
        let angle = n.dot(&pn).clamp(-1.0, 1.0).acos();
        if angle <= MAX_ANGLE {
            stats.max_angle = stats.max_angle.max(angle);
        } else {
            let parry_sep = separation64(&a64, &b64, &pn.cast::<f64>().normalize());
            let pair = BoxPair::new(a, pose_a, b, pose_b);
            let best = SatQuery::new(&pair).max_separation() as f64;
            let slack = preference_slack(&pair, &SatQuery::new(&pair)) as f64;
            if ours_sep >= parry_sep - rounding {
                stats.parry_direction_no_better += 1;
            } else if exact <= 0.0 && ours_sep >= best - slack - band {
                exempt = true;
                stats.exemptions += 1;
            } else if exact > 0.0
                && ours_sep >= exact - (WITNESS_TOL * pair.noise_scale()) as f64 - rounding
            {
                // Apart, a tie between two closest-pair candidates within the witness tolerance:
                // the distance is flat around its maximum, so near-equal directions can differ.
                exempt = true;
                stats.exemptions += 1;
            } else {
                fail(format!(
                    "normal off by {angle} rad: ours {n:?} parry {pn:?}, separation along ours {ours_sep}, along parry's {parry_sep}, kind {:?}",
                    m.kind
                ));
            }
        }
    }

    // Deepest depth against the reference's penetration (or minus its distance when apart).
    stats.max_exact_depth_error = stats
        .max_exact_depth_error
        .max((m.max_depth() as f64 + exact).abs() / size);
    if !exempt {
        let depth_error = (m.max_depth() as f64 + reference).abs();
        stats.max_depth_error = stats.max_depth_error.max(depth_error / size);
        if depth_error > band {
            fail(format!(
                "depth {} vs reference {} (exact {}), kind {:?}",
                m.max_depth(),
                -reference,
                -exact,
                m.kind
            ));
        }
    }

    // Every point, against what its feature pair says it is.
    let ulp = Real::EPSILON as f64 * coordinates;
    check_points(&m, &a64, &b64, ulp, &mut stats.points, &mut fail);

    // Reduction keeps at least half the clipped area.
    if matches!(m.kind, FeatureKind::FaceA | FeatureKind::FaceB) {
        let polygon =
            contact_polygon(a, pose_a, b, pose_b, MARGIN, None).expect("same inputs, same contact");
        if polygon.len > 4 {
            let full: Vec<Point3> = polygon.points().iter().map(|c| c.position).collect();
            let kept: Vec<Point3> = m.points().iter().map(|c| c.position).collect();
            let full_area = hull_area(&full, &n);
            // Below 1e-6 size^2 the polygon is a sliver whose area is rounding noise.
            if full_area as f64 > 1e-6 * size * size {
                stats.face_polygons_reduced += 1;
                let ratio = hull_area(&kept, &n) / full_area;
                stats.min_area_ratio = stats.min_area_ratio.min(ratio);
                if ratio < 0.5 {
                    fail(format!("reduced area ratio {ratio}"));
                }
            }
        }
    }
}

pub(super) fn report(stats: &Stats) {
    println!(
        "pairs {} (overlapping {}, within margin {}, apart {}); parry gave up on {} and was off the exact \
         signed distance by more than 5e-5 of the size on {}; presence checked {} skipped {}; contacts {}; \
         exemptions {} ({:.3} %); normals off parry's where parry's is no better {}; max angle {:.2e} rad; \
         max depth error {:.2e} of size ({:.2e} against the exact depth, exemptions included); reduced face polygons {} with min \
         area ratio {:.3}",
        stats.pairs,
        stats.overlapping,
        stats.within_margin,
        stats.apart,
        stats.parry_gave_up,
        stats.parry_off_exact,
        stats.presence_checked,
        stats.presence_skipped,
        stats.both_contact,
        stats.exemptions,
        100.0 * stats.exemptions as f64 / stats.both_contact.max(1) as f64,
        stats.parry_direction_no_better,
        stats.max_angle,
        stats.max_depth_error,
        stats.max_exact_depth_error,
        stats.face_polygons_reduced,
        stats.min_area_ratio,
    );
    println!("points: {:?}", stats.points);
    for f in stats.failures.iter().take(10) {
        println!("FAIL {f}");
    }
}
