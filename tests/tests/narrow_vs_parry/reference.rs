//! The exact f64 reference both engines are measured against, and parry's answer in the
//! pair's own units.

use super::*;

impl Box64 {
    pub(super) fn new(c: &Cuboid, pose: &Pose) -> Self {
        let pose64: nalgebra::Isometry3<f64> = pose.cast();
        let r = pose64.rotation.to_rotation_matrix();
        Self {
            centre: pose64.translation.vector,
            axes: std::array::from_fn(|k| r.matrix().column(k).into_owned()),
            half: std::array::from_fn(|k| c.half_extents[k] as f64),
        }
    }

    pub(super) fn vertex(&self, v: usize) -> V64 {
        (0..3).fold(self.centre, |p, k| {
            p + self.axes[k]
                * if v & (1 << k) != 0 {
                    self.half[k]
                } else {
                    -self.half[k]
                }
        })
    }

    /// Extent of the box's projection on unit `n`: (min, max).
    pub(super) fn project(&self, n: &V64) -> (f64, f64) {
        let c = self.centre.dot(n);
        let r: f64 = (0..3)
            .map(|k| self.half[k] * self.axes[k].dot(n).abs())
            .sum();
        (c - r, c + r)
    }

    /// `p` in the box's local frame.
    pub(super) fn local(&self, p: &V64) -> V64 {
        let d = p - self.centre;
        V64::new(
            d.dot(&self.axes[0]),
            d.dot(&self.axes[1]),
            d.dot(&self.axes[2]),
        )
    }

    /// The point of the solid box nearest to `p`.
    pub(super) fn closest_point(&self, p: &V64) -> V64 {
        let x = self.local(p);
        (0..3).fold(self.centre, |q, k| {
            q + self.axes[k] * x[k].clamp(-self.half[k], self.half[k])
        })
    }

    /// Signed distance from `p` to the box's surface: the Euclidean distance outside, minus the
    /// distance to the nearest face inside. Unlike `distance_to_point`, it tells how deep a point
    /// is, so "inside by at most `d`" is a real test.
    pub(super) fn signed_distance(&self, p: &V64) -> f64 {
        let x = self.local(p);
        let out: [f64; 3] = std::array::from_fn(|k| x[k].abs() - self.half[k]);
        let outside: f64 = out.iter().map(|o| o.max(0.0).powi(2)).sum();
        if outside > 0.0 {
            outside.sqrt()
        } else {
            out[0].max(out[1]).max(out[2])
        }
    }

    /// Outward unit normal of face `f` (axis `f / 2`, positive when `f` is even) and the plane's
    /// offset along it.
    pub(super) fn face_plane(&self, f: usize) -> (V64, f64) {
        let sign = if f.is_multiple_of(2) { 1.0 } else { -1.0 };
        let n = self.axes[f / 2] * sign;
        (n, n.dot(&self.centre) + self.half[f / 2])
    }

    pub(super) fn distance_to_point(&self, p: &V64) -> f64 {
        let d = p - self.centre;
        (0..3)
            .map(|k| {
                let x = d.dot(&self.axes[k]);
                let out = x.abs() - self.half[k];
                if out > 0.0 { out * out } else { 0.0 }
            })
            .sum::<f64>()
            .sqrt()
    }
}

/// Separation of B's projection beyond A's along unit `n` (A to B): the largest value over all
/// directions is minus the penetration depth, or the distance when the boxes are apart.
pub(super) fn separation64(a: &Box64, b: &Box64, n: &V64) -> f64 {
    b.project(n).0 - a.project(n).1
}

/// Closest points of two segments in f64 (clamped parameters, parallel case handled by clamping).
pub(super) fn segment_closest64(p1: V64, q1: V64, p2: V64, q2: V64) -> (V64, V64) {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.dot(&d1), d2.dot(&d2), d2.dot(&r));
    let (c, b) = (d1.dot(&r), d1.dot(&d2));
    let denom = a * e - b * b;
    let mut s = if denom > 1e-18 * a * e {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    (p1 + d1 * s, p2 + d2 * t)
}

/// Distance between two segments in f64.
pub(super) fn segment_distance64(p1: V64, q1: V64, p2: V64, q2: V64) -> f64 {
    let (x, y) = segment_closest64(p1, q1, p2, q2);
    (x - y).norm()
}

/// The exact signed distance in f64: overlapping, the largest separation over the 15 SAT axes
/// (minus the penetration depth, exact for polytopes); apart, the smallest of the 16
/// vertex-to-box and 144 edge-to-edge distances (every closest pair of two boxes is one of these).
pub(super) fn exact_signed_distance(a: &Box64, b: &Box64) -> f64 {
    let mut axes: Vec<V64> = a.axes.iter().chain(b.axes.iter()).copied().collect();
    for i in 0..3 {
        for j in 0..3 {
            let c = a.axes[i].cross(&b.axes[j]);
            if c.norm() > 1e-9 {
                axes.push(c.normalize());
            }
        }
    }
    let best = axes
        .iter()
        .map(|n| separation64(a, b, n).max(separation64(a, b, &-n)))
        .fold(f64::NEG_INFINITY, f64::max);
    if best <= 0.0 {
        return best;
    }
    let mut d = f64::INFINITY;
    for v in 0..8 {
        d = d
            .min(a.distance_to_point(&b.vertex(v)))
            .min(b.distance_to_point(&a.vertex(v)));
    }
    let edges = |x: &Box64| -> Vec<(V64, V64)> {
        tumble_geometry::CUBOID_EDGES
            .iter()
            .map(|[u, v]| (x.vertex(*u), x.vertex(*v)))
            .collect()
    };
    for (p1, q1) in edges(a) {
        for &(p2, q2) in &edges(b) {
            d = d.min(segment_distance64(p1, q1, p2, q2));
        }
    }
    d
}

/// parry's `contact`, given the pair in A's frame and in units of the pair's size: its GJK and
/// EPA stop on absolute tolerances (1.2e-6, 1.2e-5), which a 1 cm box would otherwise feel.
/// Returns (signed distance, world normal from A to B); `None` past `prediction`, or where EPA
/// gives up (it then reports nothing, even for overlapping boxes).
pub(super) fn parry_contact(
    a: &Cuboid,
    pa: &Pose,
    b: &Cuboid,
    pb: &Pose,
    prediction: Real,
) -> Option<(Real, Vec3)> {
    let scale = 2.0 * a.half_extents.max().max(b.half_extents.max());
    let relative: nalgebra::Isometry3<f64> = pa.cast::<f64>().inverse() * pb.cast::<f64>();
    let t = relative.translation.vector / scale as f64;
    let q = relative.rotation.quaternion().coords; // (i, j, k, w)
    let pose2 = PPose::from_parts(
        PVec::new(t.x as Real, t.y as Real, t.z as Real),
        PRot::from_xyzw(q.x as Real, q.y as Real, q.z as Real, q.w as Real),
    );
    let shape = |c: &Cuboid| {
        let h = c.half_extents / scale;
        PCuboid::new(PVec::new(h.x, h.y, h.z))
    };
    let c = parry3d::query::contact(
        &PPose::IDENTITY,
        &shape(a),
        &pose2,
        &shape(b),
        prediction / scale,
    )
    .expect("cuboids are supported")?;
    let n = pa.rotation * Vec3::new(c.normal1.x, c.normal1.y, c.normal1.z);
    Some((c.dist * scale, n))
}
