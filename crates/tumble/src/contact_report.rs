//! Contacts of the last step as users see them: by handle, in world space.

use tumble_geometry::{FeatureKind, Point3, Real, Vec3};

use crate::BodyHandle;

/// One point of a reported contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactPointReport {
    /// World position, midway between the surfaces.
    pub position: Point3,
    /// Overlap at the start of the step, m (negative: apart, within the speculative margin).
    pub depth: Real,
    /// Normal impulse applied over the step, N s.
    pub normal_impulse: Real,
    /// Feature id from the narrow phase (stable while the same features touch).
    pub id: u32,
}

/// One manifold of the last step.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactReport {
    /// Body A.
    pub body_a: BodyHandle,
    /// Body B.
    pub body_b: BodyHandle,
    /// Unit normal from A to B.
    pub normal: Vec3,
    /// Which SAT axis kind made the manifold.
    pub kind: FeatureKind,
    /// Reference face or packed edge pair.
    pub feature: u32,
    /// The points (1 to 4).
    pub points: Vec<ContactPointReport>,
}

impl ContactReport {
    /// The deepest overlap of the manifold, m.
    pub fn max_depth(&self) -> Real {
        self.points
            .iter()
            .map(|p| p.depth)
            .fold(Real::NEG_INFINITY, Real::max)
    }

    /// The manifold's total normal impulse over the step, N s.
    pub fn normal_impulse(&self) -> Real {
        self.points.iter().map(|p| p.normal_impulse).sum()
    }
}
