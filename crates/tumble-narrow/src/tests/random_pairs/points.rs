//! Every contact point against the exact geometry of the features its id names.

use super::*;

/// The packed id fields of a face contact point: (kind, reference, incident, edge_in, edge_out).
pub(super) fn face_id_fields(id: u32) -> (u32, u32, u32, u32, u32) {
    (
        id >> 14,
        (id >> 11) & 7,
        (id >> 8) & 7,
        (id >> 4) & 15,
        id & 15,
    )
}

pub(super) fn v64(p: &tumble_geometry::Point3) -> V64 {
    p.coords.cast()
}

/// Distance of `p` from segment `a b`.
pub(super) fn segment_distance(p: &V64, a: &V64, b: &V64) -> f64 {
    let d = b - a;
    let t = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
    (a + d * t - p).norm()
}

/// The points of a face contact. A point `p` of depth `d` claims to be midway between the
/// reference face and the incident surface along the normal `n`: `p + n d / 2` on A and
/// `p - n d / 2` on B. So the reference witness must lie in the reference face (on its plane,
/// within its side planes), the incident witness on the incident box's surface, `d` must be the
/// incident witness's height below the face plane, and the two labels of its id must name two
/// features the point lies on: an incident face edge (`0..4`, edge `k` from corner `k` to
/// `k + 1` of `CUBOID_FACES[incident]`) or a side plane of the reference face (`4..8`).
/// Finally the set of labels must be the exact clipped polygon's, within the margin.
pub(super) fn check_face_points(
    st: &mut Stats,
    label: &str,
    polygon: &ContactPolygon,
    a: &Box64,
    b: &Box64,
    ulp: f64,
    band: f64,
) {
    let kind = polygon.kind;
    let f = polygon.feature as usize;
    if f >= 6 {
        st.fail(format!("{label}: face feature {f}"));
        return;
    }
    let (reference, incident, towards, kind_code) = if kind == FeatureKind::FaceA {
        (a, b, 1.0, KIND_FACE_A)
    } else {
        (b, a, -1.0, KIND_FACE_B)
    };
    let axis = f / 2;
    let sign = if f.is_multiple_of(2) { 1.0 } else { -1.0 };
    let face_n = reference.face_normal(f);
    let n: V64 = polygon.normal.cast();
    st.bounded(
        true,
        (n * towards - face_n).norm(),
        Real::EPSILON as f64,
        || format!("{label}: {kind:?} normal {n:?} is not face {f}'s {face_n:?}"),
    );
    let clip: FaceClip = clip_face(reference, f, incident);
    let mut labels = BTreeSet::new();
    for c in polygon.points() {
        let (p, d) = (v64(&c.position), c.depth as f64);
        let (wa, wb) = (p + n * (0.5 * d), p - n * (0.5 * d));
        let (on_ref, on_inc) = if kind == FeatureKind::FaceA {
            (wa, wb)
        } else {
            (wb, wa)
        };
        let what = |q: &str| format!("{label}: {kind:?} {f} point {p:?} depth {d}: {q}");
        let x = reference.local(&on_ref);
        st.bounded(
            false,
            (sign * x[axis] - reference.half[axis]).abs(),
            ulp,
            || what("reference witness off the face plane"),
        );
        for k in (0..3).filter(|&k| k != axis) {
            st.bounded(
                false,
                (x[k].abs() - reference.half[k]).max(0.0),
                ulp,
                || what("reference witness outside the face"),
            );
        }
        st.bounded(false, incident.signed_distance(&on_inc).abs(), ulp, || {
            what("incident witness off the incident surface")
        });
        let height = reference.half[axis] - sign * reference.local(&on_inc)[axis];
        st.bounded(false, (d - height).abs(), ulp, || {
            what(&format!("the incident witness is {height} below the face"))
        });
        if c.depth < -MARGIN {
            st.fail(what("deeper than the margin allows"));
        }
        let (k_id, reference_id, incident_id, edge_in, edge_out) = face_id_fields(c.id);
        if id_kind(c.id) != kind_code || k_id != kind_code || reference_id != f as u32 {
            st.fail(what(&format!("id {:#x}: kind or reference field", c.id)));
        }
        if clip.incident_gap > 1e-6 && incident_id != clip.incident_face as u32 {
            st.fail(what(&format!(
                "id {:#x}: incident face {incident_id}, exact {}",
                c.id, clip.incident_face
            )));
        }
        if edge_in == edge_out || edge_in >= 8 || edge_out >= 8 {
            st.fail(what(&format!(
                "id {:#x}: labels {edge_in} {edge_out}",
                c.id
            )));
            continue;
        }
        let incident_face = incident_id as usize % 6;
        for l in [edge_in, edge_out] {
            if l < 4 {
                let corners = CUBOID_FACES[incident_face];
                let (u, v) = (
                    incident.vertex(corners[l as usize]),
                    incident.vertex(corners[(l as usize + 1) % 4]),
                );
                st.bounded(false, segment_distance(&on_inc, &u, &v), ulp, || {
                    what(&format!("id {:#x}: not on incident edge {l}", c.id))
                });
            } else {
                let (k, s) = side_plane(axis, l);
                st.bounded(false, (s * x[k] - reference.half[k]).abs(), ulp, || {
                    what(&format!("id {:#x}: not on side plane {l}", c.id))
                });
            }
        }
        labels.insert((edge_in, edge_out));
    }
    // The exact clip, where it is not within rounding of changing shape or of the margin.
    let settled = clip.incident_gap > 1e-6
        && clip.nearest_plane > band
        && clip
            .vertices
            .iter()
            .all(|v| (v.depth + MARGIN as f64).abs() > band);
    if settled {
        st.polygon_counts_compared += 1;
        let exact: BTreeSet<(u32, u32)> = clip
            .vertices
            .iter()
            .filter(|v| v.depth >= -(MARGIN as f64))
            .map(|v| (v.edge_in, v.edge_out))
            .collect();
        if exact != labels {
            st.fail(format!(
                "{label}: clipped polygon labels {labels:?}, exact {exact:?}"
            ));
        }
    }
}

/// The one point of an edge or vertex contact, against the exact pair of points it names:
/// for an edge pair (`feature = edge_a * 12 + edge_b`), the exact closest points of the two
/// edges, with the normal their exact cross product (oriented from A to B) and the depth the
/// exact overlap along it; for a vertex (`144 + v` of B, `152 + v` of A), the vertex and the
/// nearest point of the other box, the normal their direction, the depth minus their distance.
/// Its id must pack the same features: `2 << 14 | edge_a << 4 | edge_b`, or
/// `3 << 14 | on_a << 4 | v`.
pub(super) fn check_edge_or_vertex_point(
    st: &mut Stats,
    label: &str,
    polygon: &ContactPolygon,
    a: &Box64,
    b: &Box64,
    ulp: f64,
) {
    let eps = Real::EPSILON as f64;
    let n: V64 = polygon.normal.cast();
    if polygon.len != 1 {
        st.fail(format!(
            "{label}: edge or vertex contact with {} points",
            polygon.len
        ));
        return;
    }
    let c = polygon.points[0];
    let feature = polygon.feature;
    let (on_a, on_b, exact_n, exact_d, normal_unit, position_unit, id) =
        if feature < EDGE_PAIR_COUNT {
            let (ea, eb) = ((feature / 12) as usize, (feature % 12) as usize);
            let axis = a.axes[ea / 4].cross(&b.axes[eb / 4]);
            let sin = axis.norm();
            let mut exact_n = axis / sin;
            if exact_n.dot(&(b.centre - a.centre)) < 0.0 {
                exact_n = -exact_n;
            }
            let (a0, a1) = a.edge(ea);
            let (b0, b1) = b.edge(eb);
            let (pa, pb) = segment_closest(a0, a1, b0, b1);
            // The closest points of two lines crossing at an angle slide along them by the
            // inputs' rounding over the sine of that angle.
            let id = (KIND_EDGE << 14) | ((ea as u32) << 4) | eb as u32;
            (
                pa,
                pb,
                exact_n,
                -separation(a, b, &exact_n),
                eps / sin,
                ulp / sin,
                id,
            )
        } else if feature < VERTEX_OF_A_FEATURE + 8 {
            let on_a = feature >= VERTEX_OF_A_FEATURE;
            let v = (feature
                - if on_a {
                    VERTEX_OF_A_FEATURE
                } else {
                    EDGE_PAIR_COUNT
                }) as usize;
            let (pa, pb) = if on_a {
                (a.vertex(v), b.closest_point(&a.vertex(v)))
            } else {
                (a.closest_point(&b.vertex(v)), b.vertex(v))
            };
            let gap = (pb - pa).norm();
            let id = (KIND_VERTEX << 14) | (u32::from(on_a) << 4) | v as u32;
            (pa, pb, (pb - pa) / gap, -gap, ulp / gap, ulp, id)
        } else {
            st.fail(format!("{label}: feature {feature} names nothing"));
            return;
        };
    let (p, d) = (v64(&c.position), c.depth as f64);
    let what = |q: &str| format!("{label}: feature {feature} point {p:?} depth {d}: {q}");
    if c.id != id {
        st.fail(what(&format!("id {:#x}, expected {id:#x}", c.id)));
    }
    st.bounded(true, (n - exact_n).norm(), normal_unit, || {
        what(&format!("normal {n:?}, exact {exact_n:?}"))
    });
    st.bounded(false, (d - exact_d).abs(), ulp, || {
        what(&format!("exact depth {exact_d}"))
    });
    let mid = 0.5 * (on_a + on_b);
    st.bounded(false, (p - mid).norm(), position_unit, || {
        what(&format!("exact midpoint {mid:?}"))
    });
    // A clamped edge end leaves part of the gap across the normal; the witnesses then miss the
    // surfaces by up to half of it.
    let gap = on_a - on_b;
    let across = (gap - exact_n * gap.dot(&exact_n)).norm();
    let (wa, wb) = (p + n * (0.5 * d), p - n * (0.5 * d));
    let off = a
        .signed_distance(&wa)
        .abs()
        .max(b.signed_distance(&wb).abs());
    st.bounded(false, (off - 0.5 * across).max(0.0), ulp, || {
        what("a witness is off its surface")
    });
    if d < -(MARGIN as f64) {
        st.fail(what("deeper than the margin allows"));
    }
}
