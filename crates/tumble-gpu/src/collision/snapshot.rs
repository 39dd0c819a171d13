//! What a readback returns: the pair list, manifolds and contact points of one step, and
//! their conversion to the CPU's types.

use tumble_geometry::{ContactPoint, Manifold, Point3, Vec3};
use tumble_solver::{Contact, PointImpulse};

use crate::kernels::collide_cuboids::kind_from_code;
use crate::kernels::compact_touching::TouchingList;
use crate::layout::{GpuAabb, GpuContact, GpuManifold, TouchingCounts, WorkList};
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
    /// Only the manifolds in contact and their points, compacted on the GPU into a dense list
    /// in pair order (with each one's pair slot): far less to copy than `manifolds`, which
    /// holds four point slots for every candidate pair.
    pub touching: bool,
}

impl ReadbackRequest {
    /// Pairs, manifolds and contacts, one slot per candidate pair.
    pub const CONTACTS: Self = Self {
        pairs: true,
        manifolds: true,
        aabbs: false,
        touching: false,
    };

    /// The manifolds in contact only, compacted: what a CPU solver needs.
    pub const TOUCHING: Self = Self {
        pairs: false,
        manifolds: false,
        aabbs: false,
        touching: true,
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
    /// Totals of the dense list (zero unless `touching` was requested).
    pub touching_counts: TouchingCounts,
    /// The manifolds in contact, dense, in pair order (empty unless requested).
    pub touching: TouchingList,
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
        (m.len > 0).then(|| to_manifold(m, self.points(k)))
    }

    /// The pairs in contact as solver contacts, with the impulses carried from last step
    /// (zero where no point matched), each with its pair slot; from the per-pair manifolds
    /// when they were read, else from the dense list.
    pub fn solver_contacts(&self) -> Vec<(u32, Contact)> {
        if self.manifolds.is_empty() {
            let t = &self.touching;
            return t
                .touching
                .iter()
                .zip(&t.manifolds)
                .map(|(at, m)| {
                    let first = at.first_point as usize;
                    let points = &t.points[first..first + m.len as usize];
                    (at.slot, to_contact(m, points))
                })
                .collect();
        }
        (0..self.manifolds.len())
            .filter(|&k| self.manifolds[k].len > 0)
            .map(|k| (k as u32, to_contact(&self.manifolds[k], self.points(k))))
            .collect()
    }
}

/// A GPU manifold and its points as the CPU's types.
pub fn to_manifold(m: &GpuManifold, points: &[GpuContact]) -> Manifold {
    let mut out = Manifold {
        normal: Vec3::new(m.normal[0], m.normal[1], m.normal[2]),
        kind: kind_from_code(m.kind),
        feature: m.feature,
        ..Default::default()
    };
    for c in points {
        out.push(ContactPoint {
            position: Point3::new(c.position[0], c.position[1], c.position[2]),
            depth: c.depth,
            id: c.id,
        });
    }
    out
}

/// A GPU manifold and its points as a solver contact with their impulses.
fn to_contact(m: &GpuManifold, points: &[GpuContact]) -> Contact {
    let mut contact = Contact::new(m.body_a, m.body_b, to_manifold(m, points));
    contact.recycled = m.recycled != 0;
    for (slot, c) in contact.impulses.iter_mut().zip(points) {
        *slot = PointImpulse {
            normal: c.normal_impulse,
            friction: Vec3::new(
                c.friction_impulse[0],
                c.friction_impulse[1],
                c.friction_impulse[2],
            ),
        };
    }
    contact
}
