//! A small per-step readback of the pair work list (count, requested, capacity) and of the
//! sleep stage's count of bodies the step moved, read two steps late: it sizes the solver
//! path choice, reports pair overflow and finds idle steps without ever making a step wait
//! for its own results.

use std::sync::{Arc, Mutex};

use crate::layout::WorkList;
use crate::{GpuContext, GpuError};

/// Steps between a step and the read of its work list. Two: the read of step `n - 2` when
/// step `n` is recorded lets step `n - 1` run meanwhile, and the result (hence the path
/// choice) does not depend on timing.
pub const STATS_LAG: usize = 2;

type MapResult = Arc<Mutex<Option<Result<(), String>>>>;

/// Longest wait for a step's work list to be mapped before reporting a device error: far
/// beyond any step (a lost device, not a slow one).
const MAP_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(60);

/// What a step's stats slot holds once read.
#[derive(Clone, Copy, Debug)]
pub struct StepStats {
    /// The step's pair work list.
    pub work: WorkList,
    /// Bodies the step moved (not fixed once its islands woke), when the sleep stage ran.
    pub active: Option<u32>,
    /// The host's change count when the step was recorded ([`StatsRing::record`]).
    pub changes: u64,
}

/// Bytes of the work list copy; the active count follows it.
const WORK_BYTES: u64 = std::mem::size_of::<WorkList>() as u64;

#[derive(Debug)]
struct Slot {
    buffer: wgpu::Buffer,
    /// Whether the active count was copied, and the change count, of the pending step.
    recorded: (bool, u64),
    pending: Option<(wgpu::SubmissionIndex, MapResult)>,
}

/// [`STATS_LAG`] staging slots used in turn.
#[derive(Debug)]
pub struct StatsRing {
    ctx: GpuContext,
    slots: Vec<Slot>,
    next: usize,
}

impl StatsRing {
    /// Empty slots on `ctx`'s device.
    pub fn new(ctx: &GpuContext) -> Self {
        let slots = (0..STATS_LAG)
            .map(|_| Slot {
                buffer: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("step stats staging"),
                    size: WORK_BYTES + 4,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                recorded: (false, 0),
                pending: None,
            })
            .collect();
        Self {
            ctx: ctx.clone(),
            slots,
            next: 0,
        }
    }

    /// The stats of the step recorded [`STATS_LAG`] steps ago, waiting for them if needed;
    /// `None` when there was none (after a reset).
    pub fn take_lagged(&mut self) -> Result<Option<StepStats>, GpuError> {
        let slot = &mut self.slots[self.next];
        let Some((index, mapped)) = slot.pending.take() else {
            return Ok(None);
        };
        // The map callback runs inside some thread's poll: ours, or another user's of the same
        // device, which may still be inside it when our wait returns. Poll until it has run.
        let deadline = std::time::Instant::now() + MAP_TIMEOUT;
        let status = loop {
            if let Some(status) = mapped.lock().expect("stats map lock").take() {
                break status;
            }
            if std::time::Instant::now() > deadline {
                return Err(GpuError::Device(
                    "step stats were not mapped in time".into(),
                ));
            }
            self.ctx
                .device
                .poll(wgpu::PollType::Wait {
                    submission_index: Some(index.clone()),
                    timeout: None,
                })
                .map_err(|e| GpuError::Device(e.to_string()))?;
            std::thread::yield_now();
        };
        status.map_err(GpuError::Device)?;
        let (work, active) = {
            let view = slot
                .buffer
                .get_mapped_range(..)
                .map_err(|e| GpuError::Device(e.to_string()))?;
            let work: WorkList = bytemuck::pod_read_unaligned(&view[..WORK_BYTES as usize]);
            let active: u32 = bytemuck::pod_read_unaligned(&view[WORK_BYTES as usize..]);
            (work, active)
        };
        slot.buffer.unmap();
        let (copied, changes) = slot.recorded;
        Ok(Some(StepStats {
            work,
            active: copied.then_some(active),
            changes,
        }))
    }

    /// Records the copy of this step's work list and, when the sleep stage ran, its count of
    /// moving bodies into the current slot; `changes` is the host's change count.
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        work: &wgpu::Buffer,
        active: Option<&wgpu::Buffer>,
        changes: u64,
    ) {
        let slot = &mut self.slots[self.next];
        encoder.copy_buffer_to_buffer(work, 0, &slot.buffer, 0, WORK_BYTES);
        if let Some(active) = active {
            encoder.copy_buffer_to_buffer(active, 0, &slot.buffer, WORK_BYTES, 4);
        }
        slot.recorded = (active.is_some(), changes);
    }

    /// Starts mapping the current slot after the submit that holds its copy.
    pub fn submitted(&mut self, index: wgpu::SubmissionIndex) {
        let slot = &mut self.slots[self.next];
        let mapped: MapResult = Arc::new(Mutex::new(None));
        let sink = mapped.clone();
        slot.buffer.map_async(wgpu::MapMode::Read, .., move |r| {
            *sink.lock().expect("stats map lock") = Some(r.map_err(|e| e.to_string()));
        });
        slot.pending = Some((index, mapped));
        self.next = (self.next + 1) % STATS_LAG;
    }

    /// Forgets every pending read (after the bodies were re-uploaded).
    pub fn reset(&mut self) -> Result<(), GpuError> {
        for _ in 0..STATS_LAG {
            self.take_lagged()?;
            self.next = (self.next + 1) % STATS_LAG;
        }
        self.next = 0;
        Ok(())
    }
}
