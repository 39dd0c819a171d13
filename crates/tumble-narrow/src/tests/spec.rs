//! The documented choice of contact feature, evaluated in `f64` on the exact geometry: which
//! axis the manifold must be built on (and so its `kind` and `feature`), from the rules in
//! `axis_choice.rs`, `collide.rs` and `tolerance.rs`:
//!
//! - the preferred axis: A's best face; B's best face when it beats A's by more than the face
//!   tolerance; the best edge axis when it beats the better face by more than the edge tolerance
//!   (the hysteresis tolerance when that edge is within 3 degrees of the chosen face's normal and
//!   the contact is shallow); last step's face while it is within the hysteresis tolerance of the
//!   best separation;
//! - overlapping: the preferred axis when its contact has points, else the deepest axis;
//! - apart: the first of (preferred, deepest, best edge) whose contact carries the closest pair
//!   (its nearest points no farther apart than its separation plus the witness tolerance), else
//!   the nearest vertex pair when within the margin, else nothing.
//!
//! Every threshold is compared with a rounding band: where the exact value is that close to a
//! threshold, the `f32` pipeline may land on either side, and the prediction says so (`Err`).

use super::reference::{
    Box64, FaceClip, Sat64, V64, best_of, clip_face, edge_cross, nearest_vertex, segment_closest,
    separation, support_edge64,
};
use crate::tolerance::{
    EDGE_ABS_TOL, EDGE_REL_TOL, FACE_B_ABS_TOL, FACE_B_REL_TOL, FACE_LIKE_EDGE_COS,
    FACE_LIKE_MAX_DEPTH, HYSTERESIS_ABS_TOL, HYSTERESIS_REL_TOL, PARALLEL_EDGE_SIN_SQ, WITNESS_TOL,
};
use crate::{EDGE_PAIR_COUNT, VERTEX_OF_A_FEATURE};
use tumble_geometry::FeatureKind;

/// One of the 15 axes, with face indices as the narrow phase numbers them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    FaceA(usize),
    FaceB(usize),
    Edge(usize),
}

/// What the manifold must be: `None` (no contact) or its `(kind, feature)`.
pub type Expected = Option<(FeatureKind, u32)>;

/// Why no prediction was made (counted by the caller, which bounds how often each happens).
pub type Ambiguous = &'static str;

/// How far a cosine computed in `f32` from rotated unit vectors may be from the exact one:
/// a few `f32` ulps of 1, and 1e-6 is about 8 of them.
const COS_BAND: f64 = 1e-6;

/// A contact built on one axis, evaluated exactly.
struct Candidate {
    has_points: bool,
    /// Distance of its nearest pair of surface points (`inf` when it has none).
    witness: f64,
    separation: f64,
    feature: (FeatureKind, u32),
}

pub struct Spec<'a> {
    pub a: &'a Box64,
    pub b: &'a Box64,
    pub sat: Sat64,
    d: V64,
    /// The pair's noise scale (largest half extent) and feature scale (the smaller box's
    /// largest half extent), as documented on `BoxPair`.
    pub noise: f64,
    pub feature_scale: f64,
    margin: f64,
    band: f64,
}

fn tolerance(separation: f64, rel: f32, abs: f32, scale: f64) -> f64 {
    rel as f64 * separation.abs() + abs as f64 * scale
}

impl<'a> Spec<'a> {
    pub fn new(a: &'a Box64, b: &'a Box64, margin: f64, band: f64) -> Self {
        let sat = Sat64::new(a, b, PARALLEL_EDGE_SIN_SQ as f64);
        Self {
            a,
            b,
            sat,
            d: b.centre - a.centre,
            noise: a.longest_half().max(b.longest_half()),
            feature_scale: a.longest_half().min(b.longest_half()),
            margin,
            band,
        }
    }

    /// `Err` when `x` is within the band of `threshold`.
    fn side(&self, x: f64, threshold: f64, what: Ambiguous) -> Result<bool, Ambiguous> {
        if (x - threshold).abs() < self.band {
            Err(what)
        } else {
            Ok(x > threshold)
        }
    }

    /// A's face facing B on axis `i`, B's face facing A on axis `j`.
    pub fn face_a_facing(&self, i: usize) -> usize {
        2 * i + usize::from(self.d.dot(&self.a.axes[i]) < 0.0)
    }

    pub fn face_b_facing(&self, j: usize) -> usize {
        2 * j + usize::from(self.d.dot(&self.b.axes[j]) > 0.0)
    }

    /// Unit normal of an axis, from A to B (`None` for a skipped edge pair).
    pub fn normal(&self, axis: Axis) -> Option<V64> {
        match axis {
            Axis::FaceA(f) => Some(self.a.face_normal(f)),
            Axis::FaceB(f) => Some(-self.b.face_normal(f)),
            Axis::Edge(k) => self.sat.edge[k].map(|_| {
                let c = edge_cross(self.a, self.b, k / 3, k % 3).normalize();
                if c.dot(&self.d) < 0.0 { -c } else { c }
            }),
        }
    }

    /// Separation along an axis, from A to B.
    pub fn axis_separation(&self, axis: Axis) -> f64 {
        self.normal(axis)
            .map_or(f64::NEG_INFINITY, |n| separation(self.a, self.b, &n))
    }

    fn edges(&self) -> [f64; 9] {
        self.sat.edge.map(|s| s.unwrap_or(f64::NEG_INFINITY))
    }

    fn face_like(&self, edge: usize, face: Axis) -> Result<bool, Ambiguous> {
        let depth = self.sat.max().min(self.axis_separation(face));
        if !self.side(
            depth,
            -(FACE_LIKE_MAX_DEPTH as f64) * self.feature_scale,
            "face-like depth threshold",
        )? {
            return Ok(false);
        }
        let (Some(e), Some(n)) = (self.normal(Axis::Edge(edge)), self.normal(face)) else {
            return Ok(false);
        };
        let cos = e.dot(&n).abs();
        if (cos - FACE_LIKE_EDGE_COS as f64).abs() < COS_BAND {
            return Err("face-like angle threshold");
        }
        Ok(cos >= FACE_LIKE_EDGE_COS as f64)
    }

    /// The axis `preferred_axis` must return.
    pub fn preferred(&self, previous: Option<(FeatureKind, u32)>) -> Result<Axis, Ambiguous> {
        let (ia, sa, gap_a) = best_of(&self.sat.face_a);
        let (jb, sb, gap_b) = best_of(&self.sat.face_b);
        let (e, se, gap_e) = best_of(&self.edges());
        if gap_a < self.band || gap_b < self.band {
            return Err("two faces of one box tie");
        }
        let mut choice = Axis::FaceA(self.face_a_facing(ia));
        let face_b_tol = tolerance(sa, FACE_B_REL_TOL, FACE_B_ABS_TOL, self.noise);
        if self.side(sb, sa + face_b_tol, "face B tolerance")? {
            choice = Axis::FaceB(self.face_b_facing(jb));
        }
        let best_face = sa.max(sb);
        let hysteresis = tolerance(
            best_face,
            HYSTERESIS_REL_TOL,
            HYSTERESIS_ABS_TOL,
            self.feature_scale,
        );
        // Two near-equal edges matter when either could be chosen or decides the face-like test.
        if gap_e < self.band && se > best_face - hysteresis - self.band {
            return Err("two edges tie");
        }
        let edge_slack = if self.face_like(e, choice)? {
            hysteresis
        } else {
            tolerance(best_face, EDGE_REL_TOL, EDGE_ABS_TOL, self.noise)
        };
        if se.is_finite() && self.side(se, best_face + edge_slack, "edge tolerance")? {
            choice = Axis::Edge(e);
        }
        let kept = match previous {
            Some((FeatureKind::FaceA, f)) if f < 6 => Some(Axis::FaceA(f as usize)),
            Some((FeatureKind::FaceB, f)) if f < 6 => Some(Axis::FaceB(f as usize)),
            _ => None,
        };
        if let Some(kept) = kept {
            let best = self.sat.max();
            let slack = tolerance(
                best,
                HYSTERESIS_REL_TOL,
                HYSTERESIS_ABS_TOL,
                self.feature_scale,
            );
            let s = self.axis_separation(kept);
            if (s - (best - slack)).abs() < self.band {
                return Err("hysteresis tolerance");
            }
            if s >= best - slack {
                choice = kept;
            }
        }
        Ok(choice)
    }

    /// The two tolerances `preference_slack` documents: A's face over B's, and the best faces
    /// over the best edge (the hysteresis tolerance when that edge is face-like for either best
    /// face, else the edge tolerance).
    pub fn preference_tolerances(&self) -> Result<(f64, f64), Ambiguous> {
        let (ia, sa, _) = best_of(&self.sat.face_a);
        let (jb, sb, _) = best_of(&self.sat.face_b);
        let (e, _, _) = best_of(&self.edges());
        let best_face = sa.max(sb);
        let face_like = self.face_like(e, Axis::FaceA(self.face_a_facing(ia)))?
            || self.face_like(e, Axis::FaceB(self.face_b_facing(jb)))?;
        let edge = if face_like {
            tolerance(
                best_face,
                HYSTERESIS_REL_TOL,
                HYSTERESIS_ABS_TOL,
                self.feature_scale,
            )
        } else {
            tolerance(best_face, EDGE_REL_TOL, EDGE_ABS_TOL, self.noise)
        };
        Ok((
            tolerance(sa, FACE_B_REL_TOL, FACE_B_ABS_TOL, self.noise),
            edge,
        ))
    }

    /// The axis of largest separation (ties: A's faces, B's, edges).
    pub fn deepest(&self) -> Result<Axis, Ambiguous> {
        let (ia, sa, gap_a) = best_of(&self.sat.face_a);
        let (jb, sb, gap_b) = best_of(&self.sat.face_b);
        let (e, se, gap_e) = best_of(&self.edges());
        let best = sa.max(sb).max(se);
        let close = |s: f64| (s - best).abs() < self.band;
        let tied = [sa, sb, se].iter().filter(|&&s| close(s)).count() > 1;
        if tied
            || (close(sa) && gap_a < self.band)
            || (close(sb) && gap_b < self.band)
            || (close(se) && gap_e < self.band)
        {
            return Err("deepest axes tie");
        }
        Ok(if sa == best {
            Axis::FaceA(self.face_a_facing(ia))
        } else if sb == best {
            Axis::FaceB(self.face_b_facing(jb))
        } else {
            Axis::Edge(e)
        })
    }

    /// The face contact of a face axis, clipped exactly.
    pub fn face_clip(&self, axis: Axis) -> FaceClip {
        match axis {
            Axis::FaceA(f) => clip_face(self.a, f, self.b),
            Axis::FaceB(f) => clip_face(self.b, f, self.a),
            Axis::Edge(_) => unreachable!("not a face axis"),
        }
    }

    /// The two support edges of edge axis `k` (A's along `normal`, B's along `-normal`), their
    /// closest points, and the packed feature `edge_a * 12 + edge_b`.
    pub fn edge_pair(&self, k: usize) -> Result<(usize, usize, V64, V64), Ambiguous> {
        let n = self.normal(Axis::Edge(k)).ok_or("skipped edge pair")?;
        let in_a = self.a.local(&(self.a.centre + n));
        let in_b = self.b.local(&(self.b.centre - n));
        let (ea, ca) = support_edge64(k / 3, &in_a);
        let (eb, cb) = support_edge64(k % 3, &in_b);
        if ca < 1e-6 || cb < 1e-6 {
            return Err("support edge tie");
        }
        let (a0, a1) = self.a.edge(ea);
        let (b0, b1) = self.b.edge(eb);
        let (pa, pb) = segment_closest(a0, a1, b0, b1);
        Ok((ea, eb, pa, pb))
    }

    fn candidate(&self, axis: Axis) -> Result<Candidate, Ambiguous> {
        let separation = self.axis_separation(axis);
        match axis {
            Axis::FaceA(f) | Axis::FaceB(f) => {
                let clip = self.face_clip(axis);
                if clip.incident_gap < COS_BAND {
                    return Err("incident faces tie");
                }
                if clip.nearest_plane < self.band {
                    return Err("a clipped vertex is on a side plane");
                }
                let mut has_points = false;
                let mut witness = f64::INFINITY;
                for v in &clip.vertices {
                    has_points |= self.side(v.depth, -self.margin, "point depth at the margin")?;
                    witness = witness.min(-v.depth);
                }
                let kind = if matches!(axis, Axis::FaceA(_)) {
                    FeatureKind::FaceA
                } else {
                    FeatureKind::FaceB
                };
                Ok(Candidate {
                    has_points,
                    witness,
                    separation,
                    feature: (kind, f as u32),
                })
            }
            Axis::Edge(k) => {
                let (ea, eb, pa, pb) = self.edge_pair(k)?;
                let n = self.normal(axis).expect("not skipped");
                let depth = (pa - pb).dot(&n);
                Ok(Candidate {
                    has_points: self.side(depth, -self.margin, "edge depth at the margin")?,
                    witness: (pa - pb).norm(),
                    separation,
                    feature: (FeatureKind::Edge, (ea * 12 + eb) as u32),
                })
            }
        }
    }

    /// The `(kind, feature)` of the manifold, or `None` for no contact.
    pub fn expected(&self, previous: Option<(FeatureKind, u32)>) -> Result<Expected, Ambiguous> {
        let best = self.sat.max();
        if self.side(best, self.margin, "SAT separation at the margin")? {
            return Ok(None);
        }
        if best.abs() < self.band {
            return Err("touching: overlap or apart is a rounding decision");
        }
        let chosen = self.preferred(previous)?;
        if best < 0.0 {
            let first = self.candidate(chosen)?;
            if first.has_points {
                return Ok(Some(first.feature));
            }
            let second = self.candidate(self.deepest()?)?;
            return Ok(second.has_points.then_some(second.feature));
        }
        let slack = WITNESS_TOL as f64 * self.noise;
        let (e, _, _) = best_of(&self.edges());
        for axis in [Ok(chosen), self.deepest(), Ok(Axis::Edge(e))] {
            let c = self.candidate(axis?)?;
            if c.has_points && !self.side(c.witness, c.separation + slack, "witness tolerance")? {
                return Ok(Some(c.feature));
            }
        }
        let v = nearest_vertex(self.a, self.b);
        if v.runner_up - v.distance < self.band {
            return Err("two vertices tie");
        }
        if self.side(v.distance, self.margin, "vertex distance at the margin")? {
            return Ok(None);
        }
        let base = if v.on_a {
            VERTEX_OF_A_FEATURE
        } else {
            EDGE_PAIR_COUNT
        };
        Ok(Some((FeatureKind::Edge, base + v.vertex as u32)))
    }
}
