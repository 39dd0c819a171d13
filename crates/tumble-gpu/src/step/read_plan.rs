//! How a GPU world's asynchronous readback is laid out: the byte size of each requested part,
//! and the snapshot decoded from the regions a step's copies filled, in recorded order.

use crate::MAX_MANIFOLD_POINTS;
use crate::layout::{GpuContact, GpuManifold, GpuPose, GpuVelocity, WorkList};
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

/// Byte sizes of the parts of a readback.
pub(super) struct ReadSizes {
    pub(super) poses: u64,
    pub(super) velocities: u64,
    pub(super) work: u64,
    pub(super) manifolds: u64,
    pub(super) points: u64,
    pub(super) tilts: u64,
    pub(super) islands: u64,
}

impl ReadSizes {
    pub(super) fn new(bodies: u64, manifolds: u64) -> Self {
        let size = |bytes: usize, count: u64| bytes as u64 * count;
        Self {
            poses: size(std::mem::size_of::<GpuPose>(), bodies),
            velocities: size(std::mem::size_of::<GpuVelocity>(), bodies),
            work: size(std::mem::size_of::<WorkList>(), 1),
            manifolds: size(std::mem::size_of::<GpuManifold>(), manifolds),
            points: size(
                std::mem::size_of::<GpuContact>(),
                manifolds * u64::from(MAX_MANIFOLD_POINTS),
            ),
            tilts: size(std::mem::size_of::<GpuTilt>(), manifolds),
            islands: size(std::mem::size_of::<u32>(), bodies),
        }
    }

    /// Staging bytes for `request`, with alignment slack per region.
    pub(super) fn total(&self, request: &ReadRequest) -> u64 {
        let slack = 2 * wgpu::MAP_ALIGNMENT;
        let mut total = 0;
        if request.poses {
            total += self.poses + slack;
        }
        if request.velocities {
            total += self.velocities + slack;
        }
        if request.contacts {
            total += self.work + self.manifolds + self.points + self.tilts + 4 * slack;
        }
        if request.sleeping {
            total += self.islands + slack;
        }
        total
    }
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
    snapshot
}
