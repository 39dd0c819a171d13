//! Named device buffers that grow on demand and are otherwise reused from step to step.

use std::collections::HashMap;

use crate::{GpuContext, GpuError};

/// Bytes of `count` values of `T`.
pub fn bytes_of<T>(count: u64) -> u64 {
    count * std::mem::size_of::<T>() as u64
}

/// Smallest allocation: also keeps every binding non-empty, which WebGPU requires.
const MIN_BUFFER_BYTES: u64 = 256;

/// Usage of every storage buffer: bound to kernels, filled by uploads and clears, read back
/// by copies, and usable as indirect dispatch arguments.
pub const STORAGE_USAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE
    .union(wgpu::BufferUsages::COPY_DST)
    .union(wgpu::BufferUsages::COPY_SRC)
    .union(wgpu::BufferUsages::INDIRECT);

/// Usage of small parameter blocks.
pub const UNIFORM_USAGE: wgpu::BufferUsages =
    wgpu::BufferUsages::UNIFORM.union(wgpu::BufferUsages::COPY_DST);

/// Buffers by name. Growing doubles the size (so a scene that grows a little each step does
/// not reallocate each step) and bumps [`BufferPool::generation`]: bind groups made before are
/// stale. A grown buffer's contents are undefined; the caller uploads again.
#[derive(Debug)]
pub struct BufferPool {
    ctx: GpuContext,
    buffers: HashMap<&'static str, wgpu::Buffer>,
    generation: u64,
}

impl BufferPool {
    /// An empty pool on `ctx`'s device.
    pub fn new(ctx: &GpuContext) -> Self {
        Self {
            ctx: ctx.clone(),
            buffers: HashMap::new(),
            generation: 0,
        }
    }

    /// Makes `name` at least `bytes` long with `usage`; true when it was (re)allocated.
    /// Errs, naming the buffer, when the device cannot bind that many bytes.
    pub fn ensure(
        &mut self,
        name: &'static str,
        bytes: u64,
        usage: wgpu::BufferUsages,
    ) -> Result<bool, GpuError> {
        let needed = bytes.max(MIN_BUFFER_BYTES);
        if let Some(existing) = self.buffers.get(name)
            && existing.size() >= needed
            && existing.usage() == usage
        {
            return Ok(false);
        }
        self.ctx.check_storage_size(name, needed)?;
        let previous = self.buffers.get(name).map_or(0, |b| b.size());
        let limit = self.ctx.limits().max_storage_buffer_binding_size;
        let size = needed
            .max(previous.saturating_mul(2).min(limit))
            .next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT * 4);
        let buffer = self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(name),
            size,
            usage,
            mapped_at_creation: false,
        });
        self.buffers.insert(name, buffer);
        self.generation += 1;
        Ok(true)
    }

    /// [`Self::ensure`] for each `(name, bytes)` in turn; true when any was (re)allocated.
    pub fn ensure_all(
        &mut self,
        sizes: &[(&'static str, u64)],
        usage: wgpu::BufferUsages,
    ) -> Result<bool, GpuError> {
        let mut grew = false;
        for &(name, bytes) in sizes {
            grew |= self.ensure(name, bytes, usage)?;
        }
        Ok(grew)
    }

    /// The buffer called `name`. Panics if it was never [`ensure`](Self::ensure)d: that is a
    /// bug in the engine, not bad user input.
    pub fn get(&self, name: &'static str) -> &wgpu::Buffer {
        self.buffers
            .get(name)
            .unwrap_or_else(|| panic!("buffer {name} used before it was allocated"))
    }

    /// Counts reallocations; bind groups built at an older generation must be rebuilt.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Total bytes held on the device.
    pub fn bytes(&self) -> u64 {
        self.buffers.values().map(|b| b.size()).sum()
    }
}
