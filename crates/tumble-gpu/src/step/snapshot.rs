//! What a GPU world reads back on request: poses, velocities, and the manifolds with their
//! solved impulses, converted to the CPU's types on demand.

use tumble_geometry::Pose;
use tumble_solver::{BodyState, Contact};

use crate::MAX_MANIFOLD_POINTS;
use crate::collision::snapshot::to_manifold;
use crate::kernels::contact_summary::ContactSummary;
use crate::kernels::velocity_from_gpu;
use crate::layout::{GpuContact, GpuManifold, GpuPose, GpuVelocity, WorkList};
use crate::solver::convert::{pose_from_gpu, read_impulses};
use crate::solver::layout::GpuTilt;

/// Which parts of the world a readback copies (only what is asked for crosses the bus).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReadRequest {
    /// Every body's pose.
    pub poses: bool,
    /// Every body's linear and angular velocity.
    pub velocities: bool,
    /// The manifolds of the step with their solved impulses.
    pub contacts: bool,
    /// Which bodies sleep (all awake while sleep is off, and then nothing is copied).
    pub sleeping: bool,
    /// The step's contact counts ([`ContactSummary`]: 32 bytes, reduced on the GPU).
    pub summary: bool,
}

impl ReadRequest {
    /// Poses and velocities.
    pub const MOTION: Self = Self {
        poses: true,
        velocities: true,
        contacts: false,
        sleeping: false,
        summary: false,
    };
    /// Everything.
    pub const ALL: Self = Self {
        poses: true,
        velocities: true,
        contacts: true,
        sleeping: true,
        summary: true,
    };
}

/// The manifolds of one step as read back.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContactSnapshot {
    /// The manifold work list (count, and requested above capacity on overflow).
    pub work: WorkList,
    /// One manifold per candidate pair (`len == 0` when not in contact).
    pub manifolds: Vec<GpuManifold>,
    /// `MAX_MANIFOLD_POINTS` points per manifold, with the impulses solved this step (and in
    /// `friction_impulse[3]` each point's normal impulse over the whole step).
    pub points: Vec<GpuContact>,
    /// The tilt impulse of each manifold at the end of the step.
    pub tilts: Vec<GpuTilt>,
}

impl ContactSnapshot {
    /// Manifold `k` with its points, as the CPU's types; `None` for a pair not in contact.
    pub fn contact(&self, k: usize) -> Option<Contact> {
        let m = &self.manifolds[k];
        if m.len == 0 {
            return None;
        }
        let per = MAX_MANIFOLD_POINTS as usize;
        let points = &self.points[k * per..(k + 1) * per];
        let manifold = to_manifold(m, &points[..(m.len as usize).min(per)]);
        let mut contact = Contact::new(m.body_a, m.body_b, manifold);
        contact.recycled = m.recycled != 0;
        read_impulses(points, &self.tilts[k], &mut contact);
        Some(contact)
    }

    /// Every manifold with points, as the CPU's contacts (bodies, geometry, impulses).
    pub fn contacts(&self) -> Vec<Contact> {
        (0..self.manifolds.len())
            .filter_map(|k| self.contact(k))
            .collect()
    }

    /// Pairs whose bodies touched this step: some point overlapped, or pushed (a speculative
    /// point that caught an approaching body), as `Contact::is_touching` decides on the CPU.
    pub fn touching_pairs(&self) -> Vec<(u32, u32)> {
        self.contacts()
            .iter()
            .filter(|c| c.is_touching())
            .map(|c| (c.body_a, c.body_b))
            .collect()
    }
}

/// One step's state as read back.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Snapshot {
    /// Steps the world had taken when the copy was recorded.
    pub step: u64,
    /// Every body's pose (empty unless requested).
    pub poses: Vec<GpuPose>,
    /// Every body's velocity (empty unless requested).
    pub velocities: Vec<GpuVelocity>,
    /// The step's manifolds (unless not requested).
    pub contacts: Option<ContactSnapshot>,
    /// Whether each body sleeps after the step (empty unless requested).
    pub sleeping: Vec<bool>,
    /// The step's contact counts (unless not requested, or before the first step).
    pub summary: Option<ContactSummary>,
}

impl Snapshot {
    /// Bodies asleep (zero unless sleeping flags were requested).
    pub fn sleeping_count(&self) -> usize {
        self.sleeping.iter().filter(|&&s| s).count()
    }

    /// Body `i`'s pose.
    pub fn pose(&self, i: usize) -> Pose {
        pose_from_gpu(&self.poses[i])
    }

    /// Body `i`'s velocities as a solver state (no in-step deltas).
    pub fn state(&self, i: usize) -> BodyState {
        let (linear, angular) = velocity_from_gpu(&self.velocities[i]);
        BodyState::moving(linear, angular)
    }
}
