//! What a readback returns: the pair list, manifolds and contact points of one step, and
//! their conversion to the CPU's types.

use tumble_geometry::{ContactPoint, Manifold, Point3, Vec3};
use tumble_solver::{Contact, PointImpulse};

use crate::kernels::collide_cuboids::kind_from_code;
use crate::layout::{GpuAabb, GpuContact, GpuManifold, WorkList};
use crate::{GpuError, MAX_MANIFOLD_POINTS};

/// Which outputs a readback copies (only what is asked for crosses the bus).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReadbackRequest {
    /// The sorted candidate pairs.
    pub pairs: bool,
    /// Manifolds and their contact points (one per pair).
    pub manifolds: bool,
    /// The AABBs.
    pub aabbs: bool,
}

impl ReadbackRequest {
    /// Pairs, manifolds and contacts: what a CPU solver needs.
    pub const CONTACTS: Self = Self {
        pairs: true,
        manifolds: true,
        aabbs: false,
    };
}

/// One step's collision outputs, as read back.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CollisionSnapshot {
    /// The pair work list: count, requested (overflow when above capacity), capacity.
    pub work: WorkList,
    /// Sorted candidate pairs `(a, b)`, `a < b` (empty unless requested).
    pub pairs: Vec<(u32, u32)>,
    /// One manifold per pair (empty unless requested).
    pub manifolds: Vec<GpuManifold>,
    /// `MAX_MANIFOLD_POINTS` points per manifold (empty unless requested).
    pub contacts: Vec<GpuContact>,
    /// One AABB per body (empty unless requested).
    pub aabbs: Vec<GpuAabb>,
}

impl CollisionSnapshot {
    /// Errs when the broad phase found more pairs than the pair buffer holds.
    pub fn check_overflow(&self) -> Result<(), GpuError> {
        if self.work.requested > self.work.capacity {
            return Err(GpuError::PairOverflow {
                requested: self.work.requested,
                capacity: self.work.capacity,
            });
        }
        Ok(())
    }

    /// The points of manifold `k` (its valid ones only).
    pub fn points(&self, k: usize) -> &[GpuContact] {
        let per = MAX_MANIFOLD_POINTS as usize;
        let len = self.manifolds[k].len as usize;
        &self.contacts[k * per..k * per + len]
    }

    /// Manifold `k` as the CPU's type; `None` for a pair not in contact.
    pub fn manifold(&self, k: usize) -> Option<Manifold> {
        let m = &self.manifolds[k];
        if m.len == 0 {
            return None;
        }
        let mut out = Manifold {
            normal: Vec3::new(m.normal[0], m.normal[1], m.normal[2]),
            kind: kind_from_code(m.kind),
            feature: m.feature,
            ..Default::default()
        };
        for c in self.points(k) {
            out.push(ContactPoint {
                position: Point3::new(c.position[0], c.position[1], c.position[2]),
                depth: c.depth,
                id: c.id,
            });
        }
        Some(out)
    }

    /// The pairs in contact as solver contacts, with the impulses carried from last step
    /// (zero where no point matched), each with its pair index in this snapshot.
    pub fn solver_contacts(&self) -> Vec<(u32, Contact)> {
        (0..self.manifolds.len())
            .filter_map(|k| {
                let manifold = self.manifold(k)?;
                let m = &self.manifolds[k];
                let mut contact = Contact::new(m.body_a, m.body_b, manifold);
                for (slot, c) in contact.impulses.iter_mut().zip(self.points(k)) {
                    *slot = PointImpulse {
                        normal: c.normal_impulse,
                        friction: Vec3::new(
                            c.friction_impulse[0],
                            c.friction_impulse[1],
                            c.friction_impulse[2],
                        ),
                    };
                }
                Some((k as u32, contact))
            })
            .collect()
    }
}
