//! The separating axis test over the 15 axes of two boxes: 3 face normals of A, 3 of B, and the 9
//! cross products of their edge directions, all in A's frame.
//!
//! The separation along a unit axis `n` (pointing from A to B) is
//! `offset . n - r_A(n) - r_B(n)`, with the projection radius `r(n) = sum_k h_k |n . axis_k|`:
//! positive when the projections are apart (then it is a lower bound of the distance), negative
//! when they overlap (then its largest value over the 15 axes is minus the penetration depth).

use crate::BoxPair;
use crate::tolerance::PARALLEL_EDGE_SIN_SQ;
use tumble_geometry::{Real, Vec3};

/// Separations along the 15 candidate axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SatQuery {
    /// Along A's axis `i`, oriented towards B (the face `2i` or `2i + 1` facing B).
    pub face_a: [Real; 3],
    /// Along B's axis `j`, oriented towards A (the face of B facing A).
    pub face_b: [Real; 3],
    /// Along `a_i x b_j` (index `3i + j`), oriented from A to B; `-inf` for a skipped
    /// (nearly parallel) pair.
    pub edge: [Real; 9],
}

/// Which of the 15 axes: its kind and index (face `0..6`, or edge axis `3i + j`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SatAxis {
    /// Face `0..6` of A.
    FaceA(usize),
    /// Face `0..6` of B.
    FaceB(usize),
    /// Edge axis `3i + j`: A's axis `i` crossed with B's axis `j`.
    Edge(usize),
}

/// Separation along A's face `face` (either of the two faces on an axis: the one facing away from
/// B gets a very negative value, never chosen as the best).
pub fn face_a_separation(pair: &BoxPair, face: usize) -> Real {
    let i = face / 2;
    let sign = if face.is_multiple_of(2) { 1.0 } else { -1.0 };
    let radius_b = pair.abs_rot.row(i).transpose().dot(&pair.b.half_extents);
    sign * pair.offset[i] - pair.a.half_extents[i] - radius_b
}

/// Separation along B's face `face`, measured outward from B (towards A).
pub fn face_b_separation(pair: &BoxPair, face: usize) -> Real {
    let j = face / 2;
    let sign = if face.is_multiple_of(2) { 1.0 } else { -1.0 };
    let radius_a = pair.abs_rot.column(j).dot(&pair.a.half_extents);
    -sign * pair.rot.column(j).dot(&pair.offset) - pair.b.half_extents[j] - radius_a
}

/// The face of A facing B on axis `i` (`2i` when B is on the positive side).
pub fn face_a_facing(pair: &BoxPair, i: usize) -> usize {
    2 * i + usize::from(pair.offset[i] < 0.0)
}

/// The face of B facing A on B's axis `j`.
pub fn face_b_facing(pair: &BoxPair, j: usize) -> usize {
    2 * j + usize::from(pair.rot.column(j).dot(&pair.offset) > 0.0)
}

/// The unit edge axis `a_i x b_j` in A's frame, oriented from A to B; `None` when the two edge
/// directions are within 1 mrad of parallel.
pub fn edge_axis(pair: &BoxPair, i: usize, j: usize) -> Option<Vec3> {
    let axis = Vec3::ith(i, 1.0).cross(&pair.rot.column(j));
    // |a_i x b_j|^2 is the sum of the two components of b_j across a_i: no cancellation.
    let len_sq = axis.norm_squared();
    if len_sq < PARALLEL_EDGE_SIN_SQ {
        return None;
    }
    let n = axis / len_sq.sqrt();
    Some(if n.dot(&pair.offset) < 0.0 { -n } else { n })
}

/// Separation along the edge axis `a_i x b_j`, from the rotation entries alone (no vector is
/// formed): with `(i1, i2)` and `(j1, j2)` the axes after `i` and `j` in cyclic order,
/// `a_i x b_j` has length `sqrt(R[i1][j]^2 + R[i2][j]^2)`, its dot with the offset is
/// `t[i2] R[i1][j] - t[i1] R[i2][j]`, and the projection radii are
/// `a[i1] |R[i2][j]| + a[i2] |R[i1][j]|` and `b[j1] |R[i][j2]| + b[j2] |R[i][j1]|`.
/// `-inf` for a pair within 1 mrad of parallel.
pub fn edge_separation(pair: &BoxPair, i: usize, j: usize) -> Real {
    let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
    let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
    let (r, abs, a, b, t) = (
        &pair.rot,
        &pair.abs_rot,
        &pair.a.half_extents,
        &pair.b.half_extents,
        &pair.offset,
    );
    let len_sq = r[(i1, j)] * r[(i1, j)] + r[(i2, j)] * r[(i2, j)];
    if len_sq < PARALLEL_EDGE_SIN_SQ {
        return Real::NEG_INFINITY;
    }
    let distance = (t[i2] * r[(i1, j)] - t[i1] * r[(i2, j)]).abs();
    let radius_a = a[i1] * abs[(i2, j)] + a[i2] * abs[(i1, j)];
    let radius_b = b[j1] * abs[(i, j2)] + b[j2] * abs[(i, j1)];
    (distance - radius_a - radius_b) / len_sq.sqrt()
}

/// Separation along a unit axis `n` of A's frame, oriented from A to B.
pub fn axis_separation(pair: &BoxPair, n: &Vec3) -> Real {
    let radius_a = n.abs().dot(&pair.a.half_extents);
    let radius_b = (pair.rot.tr_mul(n)).abs().dot(&pair.b.half_extents);
    n.dot(&pair.offset) - radius_a - radius_b
}

impl SatQuery {
    /// Runs the 15 axis tests.
    pub fn new(pair: &BoxPair) -> Self {
        let face_a = std::array::from_fn(|i| face_a_separation(pair, face_a_facing(pair, i)));
        let face_b = std::array::from_fn(|j| face_b_separation(pair, face_b_facing(pair, j)));
        let edge = std::array::from_fn(|k| edge_separation(pair, k / 3, k % 3));
        Self {
            face_a,
            face_b,
            edge,
        }
    }

    /// The best face axis of A: (face index facing B, separation); first axis wins ties.
    pub fn best_face_a(&self, pair: &BoxPair) -> (usize, Real) {
        let i = argmax(&self.face_a);
        (face_a_facing(pair, i), self.face_a[i])
    }

    /// The best face axis of B: (face index facing A, separation).
    pub fn best_face_b(&self, pair: &BoxPair) -> (usize, Real) {
        let j = argmax(&self.face_b);
        (face_b_facing(pair, j), self.face_b[j])
    }

    /// The best edge axis: (`3i + j`, separation), `-inf` when every pair was skipped.
    pub fn best_edge(&self) -> (usize, Real) {
        let k = argmax(&self.edge);
        (k, self.edge[k])
    }

    /// The largest separation over the 15 axes: minus the penetration depth when the boxes
    /// overlap, a lower bound of their distance when they do not.
    pub fn max_separation(&self) -> Real {
        self.face_a
            .iter()
            .chain(&self.face_b)
            .chain(&self.edge)
            .fold(Real::NEG_INFINITY, |m, &s| m.max(s))
    }
}

/// Index of the first largest value.
fn argmax<const N: usize>(values: &[Real; N]) -> usize {
    let mut best = 0;
    for k in 1..N {
        if values[k] > values[best] {
            best = k;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tests::{aligned_pair, at, crossed_edges, cube};
    use tumble_geometry::{Cuboid, Pose, Rot};

    #[test]
    fn aligned_boxes_separate_exactly_along_the_offset_axis() {
        // Unit cubes whose centres are 2.5 apart along axis k: gap 0.5 on A's +k face (2k) and
        // B's -k face (2k + 1).
        for k in 0..3 {
            let p = aligned_pair(Vec3::ith(k, 2.5));
            let q = SatQuery::new(&p);
            assert_eq!(q.best_face_a(&p), (2 * k, 0.5), "axis {k}");
            assert_eq!(q.best_face_b(&p), (2 * k + 1, 0.5), "axis {k}");
            assert_eq!(q.max_separation(), 0.5, "axis {k}");
            // Every edge pair of aligned boxes is parallel or a face normal in disguise; none
            // beats 0.5.
            assert!(q.edge.iter().all(|&s| s <= 0.5), "axis {k}");
        }
    }

    #[test]
    fn overlap_depth_is_the_smallest_overlap_over_the_axes() {
        // B sunk 0.2 into A's top face and offset sideways by 1.5 (overlap 0.5 on x): depth 0.2.
        let p = aligned_pair(Vec3::new(1.5, 1.8, 0.0));
        let q = SatQuery::new(&p);
        assert!((q.max_separation() + 0.2).abs() < 1e-6);
        assert_eq!(q.best_face_a(&p).0, 2);
    }

    #[test]
    fn crossed_edges_separate_along_their_cross_product() {
        // Two unit cubes each turned 45 degrees, A about z and B about x, so that A's top edge
        // (along z) and B's bottom edge (along x) cross above one another: the edge axis is y.
        let (pose_a, pose_b) = crossed_edges(1.0, 0.1);
        let p = BoxPair::new(&cube(1.0), &pose_a, &cube(1.0), &pose_b);
        let q = SatQuery::new(&p);
        // A's top edge is at height sqrt 2, B's bottom edge at 0.1 + sqrt 2: gap 0.1, reached only
        // by the edge axis (the faces are all at 45 degrees to y).
        let (_, edge_sep) = q.best_edge();
        assert!((edge_sep - 0.1).abs() < 1e-5, "edge separation {edge_sep}");
        assert!(q.best_face_a(&p).1 < 0.1 && q.best_face_b(&p).1 < 0.1);
    }

    #[test]
    fn the_closed_form_edge_separation_matches_the_projection_on_the_normalised_axis() {
        let a = Cuboid::new(Vec3::new(0.3, 1.2, 0.7));
        let b = Cuboid::new(Vec3::new(2.0, 0.1, 0.4));
        let pose_b = at(0.9, -1.4, 2.2, Rot::from_euler_angles(0.4, -1.3, 2.9));
        let p = BoxPair::new(&a, &Pose::identity(), &b, &pose_b);
        for k in 0..9 {
            let n = edge_axis(&p, k / 3, k % 3).expect("generic rotation: no parallel edges");
            // Two evaluations of the same number in f32: a few ulps of the coordinates apart.
            assert!((edge_separation(&p, k / 3, k % 3) - axis_separation(&p, &n)).abs() < 1e-5);
        }
    }

    #[test]
    fn parallel_edge_pairs_are_skipped() {
        let p = aligned_pair(Vec3::new(0.3, 0.1, 5.0));
        let q = SatQuery::new(&p);
        // Aligned boxes: a_i x b_i is zero for i = 0, 1, 2, the diagonal 3i + i.
        for i in 0..3 {
            assert_eq!(q.edge[3 * i + i], Real::NEG_INFINITY);
        }
    }
}
