//! Asynchronous, double-buffered readback of device buffers.
//!
//! A step's command stream ends with copies of what the caller asked for into one of two
//! staging buffers; after the submit the staging buffer is mapped asynchronously. While the
//! host reads one staging buffer, the next step can copy into the other, so reading step `n`
//! never stalls recording step `n + 1`.

use std::sync::{Arc, Mutex};

use crate::{GpuContext, GpuError};

/// Where a copied region landed in a staging buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Region {
    /// Byte offset in the staging buffer.
    pub offset: u64,
    /// Length in bytes.
    pub len: u64,
}

/// What a map callback reported.
pub(crate) type MapResult = Arc<Mutex<Option<Result<(), String>>>>;

#[derive(Debug)]
struct Slot {
    buffer: Option<wgpu::Buffer>,
    used: u64,
    mapped: Option<MapResult>,
}

/// A readback in flight: staging slot and the regions copied into it.
#[derive(Debug)]
#[must_use = "a readback must be waited for"]
pub struct Ticket {
    slot: usize,
}

/// Two staging buffers used alternately.
#[derive(Debug)]
pub struct Readback {
    ctx: GpuContext,
    slots: [Slot; 2],
    next: usize,
}

impl Readback {
    /// Two empty staging slots on `ctx`'s device.
    pub fn new(ctx: &GpuContext) -> Self {
        let empty = || Slot {
            buffer: None,
            used: 0,
            mapped: None,
        };
        Self {
            ctx: ctx.clone(),
            slots: [empty(), empty()],
            next: 0,
        }
    }

    /// Starts filling the next staging slot, sized for at least `bytes`. A slot still mapped
    /// from an older readback that was never read is released first.
    pub fn begin(&mut self, bytes: u64) -> Result<usize, GpuError> {
        let index = self.next;
        self.next = 1 - self.next;
        let slot = &mut self.slots[index];
        if slot.mapped.take().is_some()
            && let Some(b) = &slot.buffer
        {
            // Wait for the pending map so unmap is legal, then drop the stale data.
            self.ctx.wait_idle()?;
            b.unmap();
        }
        let needed = bytes
            .next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT)
            .max(wgpu::COPY_BUFFER_ALIGNMENT);
        if slot.buffer.as_ref().is_none_or(|b| b.size() < needed) {
            slot.buffer = Some(self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback staging"),
                size: needed.next_power_of_two(),
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        slot.used = 0;
        Ok(index)
    }

    /// Records a copy of `len` bytes of `source` (from `offset`) into slot `slot`.
    pub fn copy(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        slot: usize,
        source: &wgpu::Buffer,
        offset: u64,
        len: u64,
    ) -> Region {
        let s = &mut self.slots[slot];
        let staging = s.buffer.as_ref().expect("begin() allocates the slot");
        let len = len.next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        assert!(
            s.used + len <= staging.size(),
            "readback slot sized too small in begin()"
        );
        let region = Region {
            offset: s.used,
            len,
        };
        if len > 0 {
            encoder.copy_buffer_to_buffer(source, offset, staging, s.used, len);
        }
        // Keep regions 8-byte aligned so each can be viewed on its own (MAP_ALIGNMENT).
        s.used = (s.used + len).next_multiple_of(wgpu::MAP_ALIGNMENT);
        region
    }

    /// Starts mapping slot `slot`; call after the submit that holds its copies.
    pub fn submitted(&mut self, slot: usize) -> Ticket {
        let s = &mut self.slots[slot];
        let result: MapResult = Arc::new(Mutex::new(None));
        let sink = result.clone();
        let staging = s.buffer.as_ref().expect("begin() allocates the slot");
        let len = s.used.max(wgpu::MAP_ALIGNMENT).min(staging.size());
        staging.map_async(wgpu::MapMode::Read, 0..len, move |r| {
            *sink.lock().expect("map callback lock") = Some(r.map_err(|e| e.to_string()));
        });
        s.mapped = Some(result);
        Ticket { slot }
    }

    /// Waits for the map and returns the bytes of every region.
    pub fn wait(&mut self, ticket: &Ticket, regions: &[Region]) -> Result<Vec<Vec<u8>>, GpuError> {
        let mapped = self.wait_mapped(ticket)?;
        regions.iter().map(|r| mapped.read::<u8>(r)).collect()
    }

    /// Waits for the map (at most the context's read timeout) and returns the mapped staging
    /// buffer.
    pub fn wait_mapped(&mut self, ticket: &Ticket) -> Result<Mapped<'_>, GpuError> {
        // A slot with no map pending fails at once in `take`.
        let slot = &self.slots[ticket.slot];
        self.ctx
            .wait_until(None, || slot.mapped.is_none() || self.is_mapped(ticket))?;
        self.take(ticket)
    }

    /// Whether the map of `ticket`'s slot has completed (its callback has run).
    fn is_mapped(&self, ticket: &Ticket) -> bool {
        self.slots[ticket.slot]
            .mapped
            .as_ref()
            .is_some_and(|m| m.lock().expect("map lock").is_some())
    }

    fn take(&mut self, ticket: &Ticket) -> Result<Mapped<'_>, GpuError> {
        let slot = &mut self.slots[ticket.slot];
        let status = slot
            .mapped
            .take()
            .and_then(|m| m.lock().expect("map lock").take())
            .ok_or_else(|| GpuError::Device("readback was not mapped".into()))?;
        status.map_err(GpuError::Device)?;
        Ok(Mapped {
            staging: slot.buffer.as_ref().expect("mapped slot has a buffer"),
        })
    }
}

/// A mapped staging buffer; unmapped when dropped.
#[derive(Debug)]
pub struct Mapped<'a> {
    staging: &'a wgpu::Buffer,
}

impl Mapped<'_> {
    /// Region `r` as a vector of `T`, copied once out of the mapping.
    pub fn read<T: bytemuck::Pod>(&self, r: &Region) -> Result<Vec<T>, GpuError> {
        let size = std::mem::size_of::<T>() as u64;
        let mut out = vec![T::zeroed(); (r.len / size) as usize];
        if r.len == 0 || out.is_empty() {
            return Ok(out);
        }
        let view = self
            .staging
            .get_mapped_range(r.offset..r.offset + r.len)
            .map_err(|e| GpuError::Device(e.to_string()))?;
        let bytes: &mut [u8] = bytemuck::cast_slice_mut(&mut out);
        let n = bytes.len();
        bytes.copy_from_slice(&view[..n]);
        Ok(out)
    }
}

impl Drop for Mapped<'_> {
    fn drop(&mut self) {
        self.staging.unmap();
    }
}
