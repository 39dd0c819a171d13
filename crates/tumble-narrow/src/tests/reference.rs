//! Exact reference geometry in `f64`, written from the definitions rather than from the `f32`
//! pipeline: boxes as a centre and three orthonormal axes, separations along an axis as the gap
//! between the two projections, closest points by minimising over the segment parameters, and
//! face clipping by Sutherland-Hodgman with the feature labels of the id layout.
//!
//! The `f32` inputs widen exactly, so every difference between these values and the narrow
//! phase's is the narrow phase's own rounding (or a bug).

use crate::feature_id::SIDE_LABEL_BASE;
use tumble_geometry::{CUBOID_EDGES, CUBOID_FACES, Cuboid, Pose, nalgebra};

/// A vector (or point) in `f64`.
pub type V64 = nalgebra::Vector3<f64>;

/// A box in world space.
#[derive(Clone, Copy, Debug)]
pub struct Box64 {
    pub centre: V64,
    /// Unit local axes in world space (columns of the rotation).
    pub axes: [V64; 3],
    pub half: [f64; 3],
}

impl Box64 {
    /// The box `c` at `pose`. The `f32` quaternion is renormalised in `f64`, so that the axes are
    /// orthonormal to `f64` precision (the distance formulas below rely on it); that moves them
    /// by about one `f32` ulp, which the tolerances of the checks cover.
    pub fn new(c: &Cuboid, pose: &Pose) -> Self {
        let q = pose.rotation.quaternion().cast::<f64>();
        let rot = nalgebra::UnitQuaternion::new_normalize(q).to_rotation_matrix();
        Self {
            centre: pose.translation.vector.cast(),
            axes: std::array::from_fn(|k| rot.matrix().column(k).into_owned()),
            half: std::array::from_fn(|k| c.half_extents[k] as f64),
        }
    }

    /// World point of local coordinates `x`.
    pub fn world(&self, x: &V64) -> V64 {
        self.centre + self.axes[0] * x[0] + self.axes[1] * x[1] + self.axes[2] * x[2]
    }

    /// Local coordinates of world point `p`.
    pub fn local(&self, p: &V64) -> V64 {
        let d = p - self.centre;
        V64::new(
            d.dot(&self.axes[0]),
            d.dot(&self.axes[1]),
            d.dot(&self.axes[2]),
        )
    }

    /// Local coordinates of vertex `v` (bit `k` set: `+h` on axis `k`).
    pub fn local_vertex(&self, v: usize) -> V64 {
        V64::from_fn(|k, _| {
            if v & (1 << k) != 0 {
                self.half[k]
            } else {
                -self.half[k]
            }
        })
    }

    pub fn vertex(&self, v: usize) -> V64 {
        self.world(&self.local_vertex(v))
    }

    /// The two world end points of edge `e` (numbered as `CUBOID_EDGES`).
    pub fn edge(&self, e: usize) -> (V64, V64) {
        let [u, v] = CUBOID_EDGES[e];
        (self.vertex(u), self.vertex(v))
    }

    /// Outward unit normal of face `f`.
    pub fn face_normal(&self, f: usize) -> V64 {
        self.axes[f / 2] * if f.is_multiple_of(2) { 1.0 } else { -1.0 }
    }

    /// Half the length of the box's projection on unit `n`.
    pub fn radius(&self, n: &V64) -> f64 {
        (0..3)
            .map(|k| self.half[k] * self.axes[k].dot(n).abs())
            .sum()
    }

    pub fn longest_half(&self) -> f64 {
        self.half[0].max(self.half[1]).max(self.half[2])
    }

    /// The point of the solid box nearest to `p`.
    pub fn closest_point(&self, p: &V64) -> V64 {
        let x = self.local(p);
        self.world(&V64::from_fn(|k, _| {
            x[k].clamp(-self.half[k], self.half[k])
        }))
    }

    /// Signed distance of `p` to the surface: the distance outside, minus the distance to the
    /// nearest face inside (so that "how deep inside" is measurable).
    pub fn signed_distance(&self, p: &V64) -> f64 {
        let x = self.local(p);
        let out = V64::from_fn(|k, _| x[k].abs() - self.half[k]);
        let outside = out.map(|o| o.max(0.0)).norm();
        if outside > 0.0 { outside } else { out.max() }
    }
}

/// Separation of B beyond A along unit `n` (from A to B): positive when the projections are
/// apart, minus their overlap otherwise.
pub fn separation(a: &Box64, b: &Box64, n: &V64) -> f64 {
    (b.centre - a.centre).dot(n) - a.radius(n) - b.radius(n)
}

/// Separation along the better orientation of the line of unit `n`.
pub fn line_separation(a: &Box64, b: &Box64, n: &V64) -> f64 {
    (b.centre - a.centre).dot(n).abs() - a.radius(n) - b.radius(n)
}

/// `a_i x b_j`, the edge axis before normalisation.
pub fn edge_cross(a: &Box64, b: &Box64, i: usize, j: usize) -> V64 {
    a.axes[i].cross(&b.axes[j])
}

/// The 15 SAT separations: A's axes, B's axes (each along its better orientation), and the
/// 9 edge cross products `3i + j` (`None` below the narrow phase's parallel threshold, which
/// is compared on the squared length of the cross product).
#[derive(Clone, Copy, Debug)]
pub struct Sat64 {
    pub face_a: [f64; 3],
    pub face_b: [f64; 3],
    pub edge: [Option<f64>; 9],
    /// `|a_i x b_j|^2`, to tell how close each pair is to the parallel threshold.
    pub edge_sin_sq: [f64; 9],
}

impl Sat64 {
    pub fn new(a: &Box64, b: &Box64, parallel_sin_sq: f64) -> Self {
        let edge_sin_sq = std::array::from_fn(|k| edge_cross(a, b, k / 3, k % 3).norm_squared());
        Self {
            face_a: std::array::from_fn(|i| line_separation(a, b, &a.axes[i])),
            face_b: std::array::from_fn(|j| line_separation(a, b, &b.axes[j])),
            edge: std::array::from_fn(|k| {
                let c = edge_cross(a, b, k / 3, k % 3);
                (edge_sin_sq[k] >= parallel_sin_sq).then(|| line_separation(a, b, &(c / c.norm())))
            }),
            edge_sin_sq,
        }
    }

    pub fn max(&self) -> f64 {
        self.face_a
            .iter()
            .chain(&self.face_b)
            .copied()
            .chain(self.edge.iter().flatten().copied())
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// The largest value (first wins ties), its index, and how far below it the runner-up is
/// (`inf` without one).
pub fn best_of(values: &[f64]) -> (usize, f64, f64) {
    let mut best = 0;
    for k in 1..values.len() {
        if values[k] > values[best] {
            best = k;
        }
    }
    let gap = (0..values.len())
        .filter(|&k| k != best)
        .map(|k| values[best] - values[k])
        .fold(f64::INFINITY, f64::min);
    (best, values[best], gap)
}

/// Closest points of segments `p0 p1` and `q0 q1` (both of non-zero length): the squared
/// distance is a convex quadratic of the two parameters, so its minimum over the unit square
/// is the stationary point when that lies inside, else the best of the four sides, each of
/// which is a clamped one-dimensional minimum.
pub fn segment_closest(p0: V64, p1: V64, q0: V64, q1: V64) -> (V64, V64) {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, b) = (d1.dot(&d1), d2.dot(&d2), d1.dot(&d2));
    let (c, f) = (d1.dot(&r), d2.dot(&r));
    let at = |s: f64, t: f64| (p0 + d1 * s, q0 + d2 * t);
    let denom = a * e - b * b;
    if denom > 1e-14 * a * e {
        let s = (b * f - c * e) / denom;
        let t = (a * f - b * c) / denom;
        if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
            return at(s, t);
        }
    }
    let sides = [
        (0.0, (f / e).clamp(0.0, 1.0)),
        (1.0, ((f + b) / e).clamp(0.0, 1.0)),
        ((-c / a).clamp(0.0, 1.0), 0.0),
        (((b - c) / a).clamp(0.0, 1.0), 1.0),
    ];
    let (s, t) = sides
        .into_iter()
        .min_by(|x, y| {
            let d = |(s, t): (f64, f64)| {
                let (u, v) = at(s, t);
                (u - v).norm_squared()
            };
            d(*x).total_cmp(&d(*y))
        })
        .expect("four sides");
    at(s, t)
}

/// The distance between the boxes when they are apart (the smallest of the 16 vertex-to-box and
/// 144 edge-to-edge distances: every closest pair of two boxes involves a vertex or two edges),
/// else the largest SAT separation (minus the penetration depth, exact for boxes).
pub fn signed_distance(a: &Box64, b: &Box64, sat: &Sat64) -> f64 {
    let best = sat.max();
    if best <= 0.0 {
        return best;
    }
    let mut d = f64::INFINITY;
    for v in 0..8 {
        d = d.min(a.signed_distance(&b.vertex(v)).max(0.0));
        d = d.min(b.signed_distance(&a.vertex(v)).max(0.0));
    }
    for ea in 0..12 {
        let (p0, p1) = a.edge(ea);
        for eb in 0..12 {
            let (q0, q1) = b.edge(eb);
            let (u, v) = segment_closest(p0, p1, q0, q1);
            d = d.min((u - v).norm());
        }
    }
    d
}

/// The vertex of either box nearest to the other box.
#[derive(Clone, Copy, Debug)]
pub struct NearestVertex {
    pub on_a: bool,
    pub vertex: usize,
    pub distance: f64,
    /// Distance of the runner-up among the 16.
    pub runner_up: f64,
}

pub fn nearest_vertex(a: &Box64, b: &Box64) -> NearestVertex {
    let mut all: Vec<NearestVertex> = Vec::with_capacity(16);
    for v in 0..8 {
        // B's vertex against A's box, then A's vertex against B's.
        for (on_a, vertex_of, other) in [(false, b, a), (true, a, b)] {
            let p = vertex_of.vertex(v);
            all.push(NearestVertex {
                on_a,
                vertex: v,
                distance: (p - other.closest_point(&p)).norm(),
                runner_up: 0.0,
            });
        }
    }
    all.sort_by(|x, y| x.distance.total_cmp(&y.distance));
    NearestVertex {
        runner_up: all[1].distance,
        ..all[0]
    }
}

/// The edge of a box along local axis `axis` farthest along local direction `dir`, in the
/// `CUBOID_EDGES` numbering (`4 axis + bit(lo) + 2 bit(hi)`, a bit set for a non-negative
/// component on that axis), and the smallest magnitude of the two components that chose it.
pub fn support_edge64(axis: usize, dir: &V64) -> (usize, f64) {
    let others: Vec<usize> = (0..3).filter(|&k| k != axis).collect();
    let bit = |k: usize| usize::from(dir[k] >= 0.0);
    (
        4 * axis + bit(others[0]) + 2 * bit(others[1]),
        dir[others[0]].abs().min(dir[others[1]].abs()),
    )
}

/// A vertex of the clipped incident face, in the reference box's local frame.
#[derive(Clone, Copy, Debug)]
pub struct ClipVertex64 {
    /// The incident point itself (on the incident face).
    pub local: V64,
    /// Depth below the reference face (positive: inside).
    pub depth: f64,
    pub edge_in: u32,
    pub edge_out: u32,
}

/// The incident face of `incident` clipped against the side planes of face `f` of `reference`.
#[derive(Clone, Debug)]
pub struct FaceClip {
    pub incident_face: usize,
    /// How much better the chosen incident face is than the runner-up (its normal's dot with
    /// the reference normal, negated): a near tie may pick either face.
    pub incident_gap: f64,
    pub vertices: Vec<ClipVertex64>,
    /// Smallest distance of a clipped vertex from a side plane it does not lie on, over all
    /// input corners and outputs: a measure of how close the clip is to changing shape.
    pub nearest_plane: f64,
}

/// The side plane of label `label` (`SIDE_LABEL_BASE + 2 slot + negative`) of the reference face
/// on axis `axis`: (local axis, sign of its outward normal).
pub fn side_plane(axis: usize, label: u32) -> (usize, f64) {
    let k = label - SIDE_LABEL_BASE;
    let others: Vec<usize> = (0..3).filter(|&m| m != axis).collect();
    (
        others[(k / 2) as usize],
        if k.is_multiple_of(2) { 1.0 } else { -1.0 },
    )
}

pub fn clip_face(reference: &Box64, f: usize, incident: &Box64) -> FaceClip {
    let axis = f / 2;
    let sign = if f.is_multiple_of(2) { 1.0 } else { -1.0 };
    let n = reference.face_normal(f);
    // The incident face: the most anti-parallel to the reference normal.
    let scores: Vec<f64> = (0..6).map(|g| -incident.face_normal(g).dot(&n)).collect();
    let (incident_face, _, incident_gap) = best_of(&scores);
    let corners: Vec<V64> = CUBOID_FACES[incident_face]
        .iter()
        .map(|&v| reference.local(&incident.vertex(v)))
        .collect();
    // Corner k carries (edge_in, edge_out) = (k - 1, k): edge k runs from corner k to k + 1.
    let mut polygon: Vec<ClipVertex64> = (0..4)
        .map(|k| ClipVertex64 {
            local: corners[k],
            depth: 0.0,
            edge_in: ((k + 3) % 4) as u32,
            edge_out: k as u32,
        })
        .collect();
    let mut nearest_plane = f64::INFINITY;
    for label in SIDE_LABEL_BASE..SIDE_LABEL_BASE + 4 {
        let (k, s) = side_plane(axis, label);
        let h = reference.half[k];
        let dist = |p: &ClipVertex64| s * p.local[k] - h;
        for p in &polygon {
            nearest_plane = nearest_plane.min(dist(p).abs());
        }
        let mut out = Vec::new();
        for m in 0..polygon.len() {
            let prev = polygon[(m + polygon.len() - 1) % polygon.len()];
            let cur = polygon[m];
            let (dp, dc) = (dist(&prev), dist(&cur));
            if (dp <= 0.0) != (dc <= 0.0) {
                let t = dp / (dp - dc);
                let local = prev.local + (cur.local - prev.local) * t;
                let (edge_in, edge_out) = if dp <= 0.0 {
                    (prev.edge_out, label)
                } else {
                    (label, prev.edge_out)
                };
                out.push(ClipVertex64 {
                    local,
                    depth: 0.0,
                    edge_in,
                    edge_out,
                });
            }
            if dc <= 0.0 {
                out.push(cur);
            }
        }
        polygon = out;
    }
    for p in &mut polygon {
        p.depth = reference.half[axis] - sign * p.local[axis];
    }
    FaceClip {
        incident_face,
        incident_gap,
        vertices: polygon,
        nearest_plane,
    }
}
