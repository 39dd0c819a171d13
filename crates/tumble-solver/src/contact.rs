//! The solver's input and output per manifold: which bodies, the manifold, and the impulses
//! carried from one step to the next.

use tumble_geometry::{MAX_MANIFOLD_POINTS, Manifold, Real, Vec3};

/// The impulses of one contact point, as stored between steps.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PointImpulse {
    /// Accumulated normal impulse of the last substep, N s (>= 0).
    pub normal: Real,
    /// Accumulated friction impulse of the last substep as a world-space vector, N s. Stored
    /// as a vector, not per tangent row, so it survives a change of tangent basis.
    pub friction: Vec3,
}

/// One manifold between two bodies, with warm-start impulses in and solved impulses out.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Contact {
    /// Index of body A in the solver's body arrays.
    pub body_a: u32,
    /// Index of body B; the manifold normal points from A to B.
    pub body_b: u32,
    /// The geometry: normal, up to four points with depths and feature ids.
    pub manifold: Manifold,
    /// In: last step's impulses matched by feature id (zero for new points).
    /// Out: the impulses at the end of this step, to be carried to the next.
    pub impulses: [PointImpulse; MAX_MANIFOLD_POINTS],
    /// Out: the normal impulse applied over the whole step per point (all substeps, warm
    /// starts, restitution), N s. Positive means the point pushed during this step.
    pub total_normal_impulse: [Real; MAX_MANIFOLD_POINTS],
    /// In/out: the patch's tilting (rolling) angular impulse as a world vector, N m s.
    pub tilt_impulse: Vec3,
    /// The narrow phase reused last step's manifold of the pair (contact recycling,
    /// [`crate::CachedManifold::recycle`]): the contact cache then keeps the anchors of the
    /// manifold last computed instead of taking this one's.
    #[cfg_attr(feature = "serde", serde(default))]
    pub recycled: bool,
}

impl Contact {
    /// A contact between bodies `a` and `b` with no warm-start impulses.
    pub fn new(body_a: u32, body_b: u32, manifold: Manifold) -> Self {
        Self {
            body_a,
            body_b,
            manifold,
            ..Self::default()
        }
    }

    /// True when some point overlaps or pushed during the last solve.
    pub fn is_touching(&self) -> bool {
        let n = self.manifold.len as usize;
        self.manifold.points().iter().any(|p| p.depth > 0.0)
            || self.total_normal_impulse[..n].iter().any(|&j| j > 0.0)
    }
}
