//! Contact manifolds: up to four points sharing one normal, each with a feature id.

use crate::{Point3, Real, Vec3};

/// The most points a manifold keeps (the thesis's reduction to a quadrilateral).
pub const MAX_MANIFOLD_POINTS: usize = 4;

/// One contact point of a manifold.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContactPoint {
    /// World-space point midway between the two surfaces along the manifold normal.
    pub position: Point3,
    /// Penetration along the normal: positive when the boxes overlap, negative when they are
    /// apart but within the speculative margin.
    pub depth: Real,
    /// Feature id: stays the same while the same pair of features (incident vertex or clipped
    /// edge against a reference face side, or edge against edge) makes this point.
    pub id: u32,
}

/// Which SAT axis produced the manifold.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum FeatureKind {
    /// Face `0..6` of box A is the reference face.
    #[default]
    FaceA,
    /// Face `0..6` of box B is the reference face.
    FaceB,
    /// An edge of A against an edge of B: a single point. Also used, with the boxes apart, for a
    /// vertex of one box against the nearest point of the other (see `Manifold::feature`).
    Edge,
}

/// A contact manifold between two boxes A and B.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Manifold {
    /// Unit normal pointing from A to B.
    pub normal: Vec3,
    /// Which kind of feature pair made the manifold.
    pub kind: FeatureKind,
    /// Reference face index for `FaceA`/`FaceB`; for `Edge`, the packed edge pair
    /// (`edge_a * 12 + edge_b`, below 144), or for a vertex contact of separated boxes
    /// `144 + v` (B's vertex `v`) or `152 + v` (A's vertex `v`); used as the hysteresis key from
    /// step to step.
    pub feature: u32,
    /// Storage for the points; only the first `len` are valid.
    pub contacts: [ContactPoint; MAX_MANIFOLD_POINTS],
    /// Number of valid points (1 to 4).
    pub len: u8,
}

impl Manifold {
    /// The valid contact points (at most four).
    pub fn points(&self) -> &[ContactPoint] {
        &self.contacts[..self.len as usize]
    }

    /// The largest penetration among the points.
    pub fn max_depth(&self) -> Real {
        self.points()
            .iter()
            .map(|p| p.depth)
            .fold(Real::NEG_INFINITY, Real::max)
    }

    /// Appends a point; returns false (and drops it) when the manifold is full.
    pub fn push(&mut self, p: ContactPoint) -> bool {
        if (self.len as usize) < MAX_MANIFOLD_POINTS {
            self.contacts[self.len as usize] = p;
            self.len += 1;
            true
        } else {
            false
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(depth: Real, id: u32) -> ContactPoint {
        ContactPoint {
            position: Point3::new(depth, 0.0, 0.0),
            depth,
            id,
        }
    }

    #[test]
    fn a_manifold_holds_four_points_and_refuses_a_fifth() {
        let mut m = Manifold::default();
        assert!(m.points().is_empty());
        for k in 0..4 {
            assert!(m.push(point(k as Real * 0.01, k)), "point {k} fits");
            assert_eq!(m.len as u32, k + 1);
        }
        assert!(!m.push(point(1.0, 9)), "a fifth point is dropped");
        assert_eq!(m.len, 4);
        let ids: Vec<u32> = m.points().iter().map(|p| p.id).collect();
        assert_eq!(ids, [0, 1, 2, 3]);
    }

    #[test]
    fn max_depth_is_the_deepest_valid_point_only() {
        let mut m = Manifold::default();
        m.push(point(-0.01, 0));
        m.push(point(0.03, 1));
        m.push(point(0.02, 2));
        assert_eq!(m.max_depth(), 0.03);
        // Stale storage past `len` must not count.
        m.contacts[3] = point(5.0, 3);
        assert_eq!(m.max_depth(), 0.03);
        // All speculative: the least negative.
        let mut apart = Manifold::default();
        apart.push(point(-0.02, 0));
        apart.push(point(-0.005, 1));
        assert_eq!(apart.max_depth(), -0.005);
    }
}
