//! A small per-step readback of the pair work list (count, requested, capacity), of the
//! sleep stage's count of bodies the step moved and of the wide path's constraints per color,
//! read two steps late: it sizes the solver path choice and the colors dispatched one by one,
//! reports pair overflow and finds idle steps without ever making a step wait for its own
//! results.

use std::sync::{Arc, Mutex};

use crate::layout::WorkList;
use crate::readback::MapResult;
use crate::solver::constants::COLOR_SLOTS;
use crate::{GpuContext, GpuError};

/// Steps between a step and the read of its work list. Two: the read of step `n - 2` when
/// step `n` is recorded lets step `n - 1` run meanwhile, and the result (hence the path
/// choice) does not depend on timing.
pub const STATS_LAG: usize = 2;

/// What a step's stats slot holds once read.
#[derive(Clone, Copy, Debug)]
pub struct StepStats {
    /// The step's pair work list.
    pub work: WorkList,
    /// Bodies the step moved (not fixed once its islands woke), when the sleep stage ran.
    pub active: Option<u32>,
    /// The host's change count when the step was recorded ([`StatsRing::record`]).
    pub changes: u64,
    /// The graph colors up to the last one the step used (its overflow set aside), when the
    /// step took the wide path.
    pub colors: Option<u32>,
    /// A wait of the step's one substep dispatch (`solve_step`) gave up (its fault word was
    /// set): the step's results may be wrong.
    pub substep_wait_gave_up: bool,
}

/// What a step's stats copy, besides its work list.
#[derive(Clone, Copy, Debug, Default)]
pub struct StatsSources<'a> {
    /// The sleep stage's count of moving bodies (`u32`), when the stage ran.
    pub active: Option<&'a wgpu::Buffer>,
    /// The wide path's per-color counts (`COLOR_SLOTS` `u32`s at the byte offset), when the
    /// step took it.
    pub color_counts: Option<(&'a wgpu::Buffer, u64)>,
    /// The one substep dispatch's fault word (a `u32` at the byte offset, nonzero when one of
    /// its waits gave up), when the step took it.
    pub substep_fault: Option<(&'a wgpu::Buffer, u64)>,
}

/// Bytes of the work list copy; the active count follows it, then the per-color counts.
const WORK_BYTES: u64 = std::mem::size_of::<WorkList>() as u64;
/// Offset of the per-color counts in a slot.
const COLORS_AT: u64 = WORK_BYTES + 4;
/// Bytes of the per-color counts.
const COLOR_BYTES: u64 = COLOR_SLOTS as u64 * 4;
/// Offset of the substep dispatch's fault word in a slot.
const FAULT_AT: u64 = COLORS_AT + COLOR_BYTES;
/// Bytes of a slot.
const SLOT_BYTES: u64 = FAULT_AT + 4;

#[derive(Debug)]
struct Slot {
    buffer: wgpu::Buffer,
    /// Whether the active count, the color counts and the fault word were copied, and the
    /// change count, of the pending step.
    recorded: (bool, bool, bool, u64),
    pending: Option<(wgpu::SubmissionIndex, MapResult)>,
    /// Stats given by [`StatsRing::preset`] (a loaded world's), taken instead of a read.
    preset: Option<StepStats>,
}

/// [`STATS_LAG`] staging slots used in turn.
#[derive(Debug)]
pub struct StatsRing {
    ctx: GpuContext,
    slots: Vec<Slot>,
    next: usize,
    /// What the last [`StatsRing::take_lagged`] returned, for [`StatsRing::undo_last`].
    last_taken: Option<StepStats>,
}

impl StatsRing {
    /// Empty slots on `ctx`'s device.
    pub fn new(ctx: &GpuContext) -> Self {
        let slots = (0..STATS_LAG)
            .map(|_| Slot {
                buffer: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("step stats staging"),
                    size: SLOT_BYTES,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                recorded: (false, false, false, 0),
                pending: None,
                preset: None,
            })
            .collect();
        Self {
            ctx: ctx.clone(),
            slots,
            next: 0,
            last_taken: None,
        }
    }

    /// The stats of the step recorded [`STATS_LAG`] steps ago, waiting for them if needed;
    /// `None` when there was none (after a reset).
    pub fn take_lagged(&mut self) -> Result<Option<StepStats>, GpuError> {
        let slot = &mut self.slots[self.next];
        if let Some(stats) = slot.preset.take() {
            self.last_taken = Some(stats);
            return Ok(Some(stats));
        }
        self.last_taken = None;
        let Some((index, mapped)) = slot.pending.take() else {
            return Ok(None);
        };
        let map_lock = || mapped.lock().expect("stats map lock");
        self.ctx.wait_until(Some(index), || map_lock().is_some())?;
        let status = map_lock().take().expect("the map callback has run");
        status.map_err(GpuError::Device)?;
        let stats = Self::decode(slot)?;
        slot.buffer.unmap();
        self.last_taken = Some(stats);
        Ok(Some(stats))
    }

    /// Undoes the last step's take and record: its own stats (waited for) are dropped and the
    /// stats it took are the next taken again (a step rolled back).
    pub fn undo_last(&mut self) -> Result<(), GpuError> {
        self.next = (self.next + STATS_LAG - 1) % STATS_LAG;
        let slot = &mut self.slots[self.next];
        if let Some((index, mapped)) = slot.pending.take() {
            let map_lock = || mapped.lock().expect("stats map lock");
            self.ctx.wait_until(Some(index), || map_lock().is_some())?;
            if matches!(map_lock().take(), Some(Ok(()))) {
                slot.buffer.unmap();
            }
        }
        slot.preset = self.last_taken.take();
        Ok(())
    }

    /// The stats of the steps not yet taken, in the order [`Self::take_lagged`] will take
    /// them, waiting for them; they stay to be taken.
    pub fn peek(&self) -> Result<Vec<Option<StepStats>>, GpuError> {
        (0..STATS_LAG)
            .map(|i| {
                let slot = &self.slots[(self.next + i) % STATS_LAG];
                if let Some(stats) = slot.preset {
                    return Ok(Some(stats));
                }
                let Some((index, mapped)) = &slot.pending else {
                    return Ok(None);
                };
                let map_lock = || mapped.lock().expect("stats map lock");
                self.ctx
                    .wait_until(Some(index.clone()), || map_lock().is_some())?;
                if let Some(Err(e)) = &*map_lock() {
                    return Err(GpuError::Device(e.clone()));
                }
                Self::decode(slot).map(Some)
            })
            .collect()
    }

    /// Makes `stats` (as [`Self::peek`] gave them) the next ones taken, in order, instead of
    /// any read pending (for a world loaded from a saved one).
    pub fn preset(&mut self, stats: impl IntoIterator<Item = Option<StepStats>>) {
        for (i, s) in stats.into_iter().take(STATS_LAG).enumerate() {
            let slot = &mut self.slots[(self.next + i) % STATS_LAG];
            slot.pending = None;
            slot.preset = s;
        }
    }

    /// The stats in `slot`'s mapped staging buffer.
    fn decode(slot: &Slot) -> Result<StepStats, GpuError> {
        let (work, active, counts, fault) = {
            let view = slot
                .buffer
                .get_mapped_range(..)
                .map_err(|e| GpuError::Device(e.to_string()))?;
            let work: WorkList = bytemuck::pod_read_unaligned(&view[..WORK_BYTES as usize]);
            let active: u32 =
                bytemuck::pod_read_unaligned(&view[WORK_BYTES as usize..COLORS_AT as usize]);
            let counts: [u32; COLOR_SLOTS as usize] =
                bytemuck::pod_read_unaligned(&view[COLORS_AT as usize..FAULT_AT as usize]);
            let fault: u32 = bytemuck::pod_read_unaligned(&view[FAULT_AT as usize..]);
            (work, active, counts, fault)
        };
        let (active_copied, colors_copied, fault_copied, changes) = slot.recorded;
        Ok(StepStats {
            work,
            active: active_copied.then_some(active),
            changes,
            colors: colors_copied.then(|| colors_used(&counts)),
            substep_wait_gave_up: fault_copied && fault != 0,
        })
    }

    /// Records the copy of this step's work list and of what `sources` names into the
    /// current slot; `changes` is the host's change count.
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        work: &wgpu::Buffer,
        sources: StatsSources<'_>,
        changes: u64,
    ) {
        let slot = &mut self.slots[self.next];
        encoder.copy_buffer_to_buffer(work, 0, &slot.buffer, 0, WORK_BYTES);
        if let Some(active) = sources.active {
            encoder.copy_buffer_to_buffer(active, 0, &slot.buffer, WORK_BYTES, 4);
        }
        if let Some((counts, offset)) = sources.color_counts {
            encoder.copy_buffer_to_buffer(counts, offset, &slot.buffer, COLORS_AT, COLOR_BYTES);
        }
        if let Some((fault, offset)) = sources.substep_fault {
            encoder.copy_buffer_to_buffer(fault, offset, &slot.buffer, FAULT_AT, 4);
        }
        slot.recorded = (
            sources.active.is_some(),
            sources.color_counts.is_some(),
            sources.substep_fault.is_some(),
            changes,
        );
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

/// The graph colors up to the last non-empty one, from per-color counts (the overflow set,
/// last, left out).
fn colors_used(counts: &[u32]) -> u32 {
    let graph = &counts[..counts.len() - 1];
    graph
        .iter()
        .rposition(|&n| n > 0)
        .map_or(0, |c| c as u32 + 1)
}

#[cfg(test)]
mod tests {
    use super::colors_used;

    #[test]
    fn colors_used_ends_at_the_last_non_empty_graph_color() {
        // The overflow set (last entry) does not count; an empty color inside the range does.
        assert_eq!(colors_used(&[3, 0, 2, 0, 0, 7]), 3);
        assert_eq!(colors_used(&[0, 0, 0, 5]), 0);
        assert_eq!(colors_used(&[1, 1, 1, 1]), 3);
    }
}
