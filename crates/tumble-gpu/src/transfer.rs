//! Blocking uploads and reads of whole buffers, for setup, tests and tools. A simulation step
//! never uses the blocking read: it goes through [`crate::Readback`].

use bytemuck::Pod;
use wgpu::util::DeviceExt;

use crate::buffer_pool::STORAGE_USAGE;
use crate::{GpuContext, GpuError};

impl GpuContext {
    /// A command encoder labelled `label`.
    pub fn encoder(&self, label: &str) -> wgpu::CommandEncoder {
        self.device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) })
    }

    /// A new storage buffer holding `data` (at least 4 bytes, so it can always be bound).
    pub fn storage_buffer<T: Pod>(&self, label: &str, data: &[T]) -> wgpu::Buffer {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        if bytes.is_empty() {
            return self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: wgpu::COPY_BUFFER_ALIGNMENT,
                usage: STORAGE_USAGE,
                mapped_at_creation: false,
            });
        }
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: STORAGE_USAGE,
            })
    }

    /// Copies `count` elements of `T` from `buffer` (starting at element `first`) back to the
    /// host, waiting for all submitted work first.
    pub fn read_buffer<T: Pod>(
        &self,
        buffer: &wgpu::Buffer,
        first: u64,
        count: u64,
    ) -> Result<Vec<T>, GpuError> {
        let size = std::mem::size_of::<T>() as u64;
        let bytes = count * size;
        if bytes == 0 {
            return Ok(Vec::new());
        }
        // Every shared type is made of 4-byte fields, so copies are always aligned.
        debug_assert_eq!(bytes % wgpu::COPY_BUFFER_ALIGNMENT, 0);
        let padded = bytes;
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("blocking read"),
            size: padded,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.encoder("read");
        encoder.copy_buffer_to_buffer(buffer, first * size, &staging, 0, padded);
        self.submit(encoder)?;
        staging.map_async(wgpu::MapMode::Read, .., |_| {});
        self.wait_idle()?;
        let data = {
            let view = staging
                .get_mapped_range(..)
                .map_err(|e| GpuError::Device(e.to_string()))?;
            bytemuck::pod_collect_to_vec(&view[..bytes as usize])
        };
        staging.unmap();
        Ok(data)
    }
}
