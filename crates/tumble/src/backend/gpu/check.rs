//! `Backend::Gpu`'s check of a step's results: the GPU's motion check flags a step that left
//! a body out of bounds; the host then checks the state exactly and, when a body is out of
//! bounds, undoes the step on the device (`tumble_gpu::step::GpuWorld::roll_back`) and here.

use tumble_geometry::Pose;
use tumble_gpu::step::ReadRequest;
use tumble_solver::{BodyKind, BodyState, bounds};

use super::{GpuBackend, Host, failed, poisoned};
use crate::gpu_reads::{Reads, Unread};
use crate::{BodyHandle, Error, StepStats};

/// What a step replaced in the backend, kept until its check passes.
pub(super) type Previous = (Option<Unread>, Reads, StepStats);

impl GpuBackend {
    /// Checks the step just submitted (waiting for it): Ok when no body left its bounds;
    /// else the step is undone and `InvalidStep` names the first such body.
    pub(super) fn check_step(
        &mut self,
        host: &mut Host,
        handles: &[BodyHandle],
        previous: Previous,
        host_current: bool,
        uploaded_before: bool,
    ) -> Result<(), Error> {
        let gpu = self.gpu.get_mut().map_err(|_| poisoned())?;
        // The step's motion check (`tumble_gpu::step::GpuWorld::set_motion_check`): a 4-byte
        // flag read when the step is done. Only a flagged step reads its state and is undone.
        if gpu.motion_flag().map_err(failed)?.is_none() {
            return Ok(());
        }
        let snap = gpu.read_now(ReadRequest::MOTION).map_err(failed)?;
        let poses: Vec<Pose> = (0..snap.poses.len()).map(|i| snap.pose(i)).collect();
        let velocities: Vec<BodyState> =
            (0..snap.velocities.len()).map(|i| snap.state(i)).collect();
        let Some(Error::InvalidGpuState {
            body,
            quantity,
            value,
            expected,
        }) = check_results(host, handles, &poses, &velocities)
        else {
            // Flagged by the kernel's float test on a bound the exact check keeps: a valid
            // state, kept.
            return Ok(());
        };
        gpu.roll_back().map_err(failed)?;
        (self.unread, self.last_asked, host.stats) = previous;
        self.uploaded_last_step = uploaded_before;
        if host_current {
            // The GPU holds the host's state again (any write the step made before it ran is
            // in the checkpoint): the step taken again must not write it a second time.
            self.synced = host
                .bodies
                .iter()
                .map(|b| b.pose)
                .zip(host.states.iter().copied())
                .collect();
        }
        Err(Error::InvalidStep {
            body,
            quantity,
            value,
            expected,
        })
    }
}

/// The error for the first moving body whose pose or velocities, as the GPU step left them,
/// leave their bounds ([`bounds::check_motion`]).
pub(crate) fn check_results(
    host: &Host,
    handles: &[BodyHandle],
    poses: &[Pose],
    velocities: &[BodyState],
) -> Option<Error> {
    (0..poses.len().min(velocities.len())).find_map(|d| {
        if host.bodies.get(d).is_none_or(|b| b.kind == BodyKind::Fixed) {
            return None;
        }
        let (p, v) = (&poses[d], &velocities[d]);
        bounds::check_motion(p, &v.linear_velocity, &v.angular_velocity).map(|e| {
            Error::InvalidGpuState {
                body: handles[d],
                quantity: e.quantity,
                value: e.value,
                expected: e.expected,
            }
        })
    })
}
