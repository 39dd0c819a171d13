//! The contact-event stage of a [`super::GpuWorld`] (`crate::kernels::contact_events`):
//! recorded after the sleep stage while events are on, read back only when asked for. Off,
//! it records nothing and holds no buffer.

use crate::collision::GpuCollision;
use crate::kernel::Kernel;
use crate::kernels::contact_events::{CONTACT_BEGINS, CONTACT_ENDS, ContactEventList};
use crate::layout::GpuContactEvent;
use crate::{GpuContext, GpuError, StageTimer};

/// Bytes of the append counters (`EventCounts`: events, touching, two pads).
const COUNTS_BYTES: u64 = 16;

/// The stage's kernels and buffers.
#[derive(Debug)]
pub(crate) struct EventStage {
    begins: Kernel,
    ends: Kernel,
    /// Pair slots the buffers hold.
    capacity: u32,
    buffers: Option<Buffers>,
    /// The collision stages' step and history resets when the stage last ran: this step's
    /// comparison is with the step before only when that was the last one it ran after, and
    /// no reset dropped that step's pairs since.
    last: Option<(u64, u64)>,
    /// Whether the last recorded pass compared with the step before (see `last`).
    compared: bool,
}

#[derive(Debug)]
struct Buffers {
    kept: wgpu::Buffer,
    counts: wgpu::Buffer,
    events: wgpu::Buffer,
    touching: wgpu::Buffer,
}

fn storage(ctx: &GpuContext, label: &str, size: u64) -> wgpu::Buffer {
    ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16),
        usage: crate::buffer_pool::STORAGE_USAGE,
        mapped_at_creation: false,
    })
}

impl EventStage {
    /// The stage's pipelines.
    pub(crate) fn new(ctx: &GpuContext) -> Result<Self, GpuError> {
        Ok(Self {
            begins: Kernel::new(ctx, &CONTACT_BEGINS)?,
            ends: Kernel::new(ctx, &CONTACT_ENDS)?,
            capacity: 0,
            buffers: None,
            last: None,
            compared: false,
        })
    }

    fn ensure_buffers(&mut self, ctx: &GpuContext, capacity: u32) {
        if self.buffers.is_none() || capacity > self.capacity {
            let event = std::mem::size_of::<GpuContactEvent>() as u64;
            let slots = u64::from(capacity);
            self.buffers = Some(Buffers {
                kept: storage(ctx, "contact events: kept", slots * 4),
                counts: storage(ctx, "contact events: counts", COUNTS_BYTES),
                // At most one begin per pair of this step and one end per pair of the last.
                events: storage(ctx, "contact events: events", 2 * slots * event),
                touching: storage(ctx, "contact events: touching", slots * event),
            });
            self.capacity = capacity;
        }
    }

    /// Records the stage after a step whose collision stages `collision` recorded.
    pub(crate) fn record(
        &mut self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        collision: &GpuCollision,
    ) {
        let now = (collision.steps(), collision.history_resets());
        self.compared = self
            .last
            .is_some_and(|(step, resets)| step + 1 == now.0 && resets == now.1);
        self.last = Some(now);
        let [current, previous] = collision.pair_sets();
        self.ensure_buffers(ctx, collision.pair_capacity());
        let b = self.buffers.as_ref().expect("made above");
        let (begins, ends) = (&self.begins, &self.ends);
        encoder.clear_buffer(&b.kept, 0, None);
        encoder.clear_buffer(&b.counts, 0, None);
        // Both kernels' bindings, by name: this step's pair set, last step's, the outputs.
        let buffer = |name: &str| match name {
            "work" => current[0],
            "manifolds" => current[1],
            "contacts" => current[2],
            "previous_work" => previous[0],
            "previous_manifolds" => previous[1],
            "previous_contacts" => previous[2],
            "kept" => &b.kept,
            "counts" => &b.counts,
            "events" => &b.events,
            "touching" => &b.touching,
            _ => unreachable!("no contact event binding {name}"),
        };
        let begin_group = begins.bind_named(ctx, buffer);
        let end_group = ends.bind_named(ctx, buffer);
        let mut pass = StageTimer::disabled(ctx).begin_pass(encoder, "contact events");
        begins.dispatch_work(&mut pass, &begin_group, current[0]);
        ends.dispatch_work(&mut pass, &end_group, previous[0]);
    }

    /// A step ran without the collision stages (host manifolds): the next pass has no step
    /// before it to compare with.
    pub(crate) fn forget(&mut self) {
        self.last = None;
    }

    /// Records an idle step (one whose work was skipped because it repeats the last): no
    /// event, the same touching pairs.
    pub(crate) fn record_idle(&mut self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(b) = &self.buffers {
            encoder.clear_buffer(&b.counts, 0, Some(4));
        }
    }

    /// The last recorded pass's lists (waiting for the GPU), whether it compared with the step
    /// before (else its events are void: the caller compares the touching pairs itself), and
    /// the bytes read.
    pub(crate) fn read(&self, ctx: &GpuContext) -> Result<(ContactEventList, bool, u64), GpuError> {
        let Some(b) = &self.buffers else {
            return Ok((ContactEventList::default(), false, 0));
        };
        let counts: Vec<u32> = ctx.read_buffer(&b.counts, 0, 4)?;
        let cap = u64::from(self.capacity);
        let events = u64::from(counts[0]).min(2 * cap);
        let touching = u64::from(counts[1]).min(cap);
        let list = ContactEventList {
            events: ctx.read_buffer(&b.events, 0, events)?,
            touching: ctx.read_buffer(&b.touching, 0, touching)?,
        };
        let event = std::mem::size_of::<GpuContactEvent>() as u64;
        Ok((
            list,
            self.compared,
            COUNTS_BYTES + (events + touching) * event,
        ))
    }
}
