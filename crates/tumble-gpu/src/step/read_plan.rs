//! A GPU world's asynchronous readback: the snapshot decoded from the regions a step's copies
//! filled, in recorded order.

use crate::MAX_MANIFOLD_POINTS;
use crate::kernels::contact_summary::{CONTACT_SUMMARY_BYTES, ContactSummary};
use crate::layout::{GpuContact, GpuManifold, WorkList};
use crate::readback::{Region, Ticket};
use crate::sleep::constants::AWAKE;
use crate::solver::layout::GpuTilt;

use super::snapshot::{ContactSnapshot, ReadRequest, Snapshot};

/// A requested read whose copies were submitted with a step.
#[derive(Debug)]
pub(super) struct PendingRead {
    pub(super) ticket: Ticket,
    pub(super) regions: Vec<Region>,
    pub(super) request: ReadRequest,
    pub(super) step: u64,
    /// True when the island labels were copied (sleep on); otherwise no body sleeps.
    pub(super) islands_copied: bool,
}

/// The snapshot in the bytes of a readback's regions, in the order they were recorded, for
/// a world of `bodies` bodies.
pub(super) fn decode(read: &PendingRead, bodies: usize, bytes: Vec<Vec<u8>>) -> Snapshot {
    let (request, step) = (&read.request, read.step);
    let mut parts = bytes.into_iter();
    let mut next = || parts.next().unwrap_or_default();
    let mut snapshot = Snapshot {
        step,
        ..Default::default()
    };
    if request.poses {
        snapshot.poses = bytemuck::pod_collect_to_vec(&next());
    }
    if request.velocities {
        snapshot.velocities = bytemuck::pod_collect_to_vec(&next());
    }
    if request.contacts {
        let work: WorkList = bytemuck::pod_read_unaligned(&next());
        let mut manifolds: Vec<GpuManifold> = bytemuck::pod_collect_to_vec(&next());
        let mut points: Vec<GpuContact> = bytemuck::pod_collect_to_vec(&next());
        let mut tilts: Vec<GpuTilt> = bytemuck::pod_collect_to_vec(&next());
        // Keep this step's manifolds only (the copy may be longer than the count).
        let count = (work.count as usize).min(manifolds.len());
        manifolds.truncate(count);
        points.truncate(count * MAX_MANIFOLD_POINTS as usize);
        tilts.truncate(count);
        snapshot.contacts = Some(ContactSnapshot {
            work,
            manifolds,
            points,
            tilts,
        });
    }
    if request.sleeping {
        snapshot.sleeping = if read.islands_copied {
            let labels: Vec<u32> = bytemuck::pod_collect_to_vec(&next());
            labels.iter().map(|&l| l != AWAKE).collect()
        } else {
            vec![false; bodies]
        };
    }
    if request.summary {
        let bytes = next();
        snapshot.summary = bytes
            .get(..CONTACT_SUMMARY_BYTES as usize)
            .map(|b| ContactSummary::from_words(bytemuck::pod_read_unaligned(b)));
    }
    snapshot
}
