//! Contact recycling: a pair whose bodies barely moved relative to each other keeps last
//! step's manifold, its points still attached to the same material points of both boxes,
//! instead of running the separating axis test and the clipping again.
//!
//! When a manifold is computed, each point leaves two anchors behind in the cache
//! ([`crate::CachedManifold`]): the point of A's surface in A's frame and the point of B's
//! surface in B's frame (the midway point moved half the depth along the normal each way), the
//! normal in both frames, and the separation's sign. At the next step the anchors are carried
//! to the world by the new poses. The manifold is reused when
//! - the normal, seen from A and from B, turned by less than one degree relative to the other
//!   body ([`RECYCLE_NORMAL_COS`]): the relative rotation is small;
//! - every point's separation along the normal kept its sign (an overlapping point still
//!   overlaps, a speculative one is still apart) and stays within the pair's margin;
//! - every point's B anchor slid, across A's normal, at most the pair's recycle tolerance
//!   from its A anchor ([`recycle_tolerance`]): the same features still face each other.
//!
//! The anchors stay those of the manifold last computed for as long as it is reused, so a
//! slow slide adds up and triggers a fresh manifold once it passes the tolerance. The reused
//! manifold's depths are exact for its material points; what it leaves out is what a fresh
//! clipping would add or move within the tolerance (a point that slid over an edge by less
//! than the tolerance, a new point of a face that tilted by less than a degree).
//!
//! The test is parry3d's `ContactManifold::try_update_contacts`, which rapier3d runs before its
//! cuboid-cuboid manifold (one degree and 1e-6 m^2 in its current source; earlier releases used
//! five degrees and 1e-3 m^2); the tolerance here also scales
//! with the smaller box, so that millimetre boxes are not given a millimetre of slack.

use tumble_geometry::{ContactPoint, Cuboid, Manifold, Point3, Pose, Real};

use crate::CachedManifold;

/// Cosine of the largest turn of the normal, seen from A against seen from B, that still
/// reuses a manifold: one degree (parry3d's `COS_1_DEGREES` in `try_update_contacts`).
pub const RECYCLE_NORMAL_COS: Real = 0.999_847_7;

/// The default largest slide of a reused point across the normal, m: 1 mm, parry3d's
/// squared-distance threshold of 1e-6 m^2.
pub const DEFAULT_RECYCLE_DISTANCE: Real = 1e-3;

/// The largest slide as a fraction of the pair's smallest half extent: a unit cube keeps the
/// full millimetre, a 1 cm box a tenth of it.
pub const RECYCLE_SIZE_FRACTION: Real = 0.01;

/// The largest slide of a reused point for boxes `a` and `b` when the world allows
/// `distance` (`WorldConfig::recycle_distance`; 0 turns recycling off): the smaller of
/// `distance` and [`RECYCLE_SIZE_FRACTION`] of the pair's smallest half extent.
pub fn recycle_tolerance(distance: Real, a: &Cuboid, b: &Cuboid) -> Real {
    let smallest = a.half_extents.min().min(b.half_extents.min());
    distance.min(RECYCLE_SIZE_FRACTION * smallest)
}

impl CachedManifold {
    /// Last step's manifold of this pair moved with the bodies to `pose_a` and `pose_b`, when
    /// it may be reused (the module's three tests, with `margin` the pair's speculative
    /// margin this step and `tolerance` its [`recycle_tolerance`]); `None` when the pair needs
    /// a fresh manifold. Points, ids, kind and feature are the cached ones; each point sits
    /// midway between its two anchors, with the depth of the anchors along A's normal.
    pub fn recycle(
        &self,
        pose_a: &Pose,
        pose_b: &Pose,
        margin: Real,
        tolerance: Real,
    ) -> Option<Manifold> {
        let len = self.len as usize;
        // 0 (recycling off), or a NaN: never reuse.
        if len == 0 || tolerance.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let normal = pose_a.rotation * self.local_normal;
        let normal_b = pose_b.rotation * self.normal_b;
        if normal.dot(&normal_b) < RECYCLE_NORMAL_COS {
            return None;
        }
        let mut manifold = Manifold {
            normal,
            kind: self.kind,
            feature: self.feature,
            ..Default::default()
        };
        let tolerance2 = tolerance * tolerance;
        for i in 0..len {
            let on_a = pose_a * Point3::from(self.anchors_a[i]);
            let on_b = pose_b * Point3::from(self.anchors_b[i]);
            let gap = on_b - on_a;
            let separation = gap.dot(&normal);
            // A point that started or stopped overlapping may bring other points with it;
            // one beyond the margin would not be reported by a fresh test.
            let overlapped = self.overlapped & (1 << i) != 0;
            if (separation <= 0.0) != overlapped || separation > margin {
                return None;
            }
            let slide = gap - normal * separation;
            let slid = slide.norm_squared();
            if slid > tolerance2 || slid.is_nan() {
                return None;
            }
            manifold.contacts[i] = ContactPoint {
                position: Point3::from((on_a.coords + on_b.coords) * 0.5),
                depth: -separation,
                id: self.ids[i],
            };
        }
        manifold.len = self.len;
        Some(manifold)
    }
}
