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
    /// Buffers every step rewrites before any kernel or host read of that step looks at
    /// them (scratch of one step): left out of checkpoints ([`Self::with_per_step`]).
    per_step: &'static [&'static str],
}

impl BufferPool {
    /// An empty pool on `ctx`'s device.
    pub fn new(ctx: &GpuContext) -> Self {
        Self {
            ctx: ctx.clone(),
            buffers: HashMap::new(),
            generation: 0,
            per_step: &[],
        }
    }

    /// The pool with `names` declared scratch of one step: every step writes them in full
    /// (as far as that step reads them) before reading them, so a checkpoint need not copy
    /// them, and a step rolled back and run again finds them as it would have. Snapshots still
    /// hold them.
    pub fn with_per_step(mut self, names: &'static [&'static str]) -> Self {
        self.per_step = names;
        self
    }

    /// The state buffers a checkpoint copies: all but the per-step scratch.
    fn checkpoint_buffers(&self) -> Vec<(&'static str, &wgpu::Buffer)> {
        let mut out = self.state_buffers();
        out.retain(|(name, _)| !self.per_step.contains(name));
        out
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

    /// Whether `name` has been [`ensure`](Self::ensure)d.
    pub fn contains(&self, name: &'static str) -> bool {
        self.buffers.contains_key(name)
    }

    /// Drops the buffers `names` (those not held are skipped); bumps the generation when any
    /// was held.
    pub fn remove(&mut self, names: &[&'static str]) {
        let before = self.buffers.len();
        self.buffers.retain(|name, _| !names.contains(name));
        if self.buffers.len() != before {
            self.generation += 1;
        }
    }

    /// Counts reallocations; bind groups built at an older generation must be rebuilt.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Total bytes held on the device.
    pub fn bytes(&self) -> u64 {
        self.buffers.values().map(|b| b.size()).sum()
    }

    /// Every buffer's name and size in bytes, in name order (for memory reports; the sizes
    /// sum to [`Self::bytes`]).
    pub fn sizes(&self) -> Vec<(&'static str, u64)> {
        let mut out: Vec<_> = self.buffers.iter().map(|(&n, b)| (n, b.size())).collect();
        out.sort_unstable_by_key(|(n, _)| *n);
        out
    }
}

/// One pooled buffer's contents as saved by [`BufferPool::save`]: its name, its size in
/// bytes, and its bytes up to the last non-zero one (a device buffer starts zeroed, so the
/// rest is zeros).
#[derive(Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SavedBuffer {
    /// The pool's name for the buffer.
    pub name: String,
    /// Its size in bytes.
    pub size: u64,
    /// Its contents, trailing zeros left out.
    pub bytes: Vec<u8>,
}

impl BufferPool {
    /// The buffers that hold state a kernel wrote (every one the device can copy from:
    /// parameter blocks, which the host writes, are left out), in name order.
    fn state_buffers(&self) -> Vec<(&'static str, &wgpu::Buffer)> {
        let mut out: Vec<_> = self
            .buffers
            .iter()
            .filter(|(_, b)| b.usage().contains(wgpu::BufferUsages::COPY_SRC))
            .map(|(&n, b)| (n, b))
            .collect();
        out.sort_unstable_by_key(|(n, _)| *n);
        out
    }

    /// Every state buffer's contents, read back (blocking, after all submitted work).
    pub fn save(&self) -> Result<Vec<SavedBuffer>, GpuError> {
        self.state_buffers()
            .into_iter()
            .map(|(name, buffer)| {
                let mut bytes: Vec<u8> = self.ctx.read_buffer(buffer, 0, buffer.size())?;
                let used = bytes.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1);
                bytes.truncate(used);
                Ok(SavedBuffer {
                    name: name.to_string(),
                    size: buffer.size(),
                    bytes,
                })
            })
            .collect()
    }

    /// Writes `saved` (from [`Self::save`] of a pool holding the same buffers) into this
    /// pool's buffers, each made exactly `saved.size` bytes. Errs, before writing anything,
    /// when the two pools do not hold the same state buffers or a buffer holds more bytes
    /// than its size, naming it.
    pub fn load(&mut self, saved: &[SavedBuffer]) -> Result<(), GpuError> {
        let mine: Vec<&'static str> = self.state_buffers().iter().map(|(n, _)| *n).collect();
        let theirs: Vec<&str> = saved.iter().map(|s| s.name.as_str()).collect();
        if mine != theirs {
            return Err(GpuError::InvalidInput {
                field: "saved buffers".into(),
                value: format!("{theirs:?} (this stage holds {mine:?})"),
            });
        }
        if let Some(s) = saved
            .iter()
            .find(|s| s.bytes.len() as u64 > s.size || s.size % wgpu::COPY_BUFFER_ALIGNMENT != 0)
        {
            return Err(GpuError::InvalidInput {
                field: format!("saved buffer {}", s.name),
                value: format!("{} bytes in a buffer of {}", s.bytes.len(), s.size),
            });
        }
        for (name, s) in mine.into_iter().zip(saved) {
            self.ctx.check_storage_size(name, s.size)?;
            let usage = self.buffers[name].usage();
            if self.buffers[name].size() != s.size {
                let buffer = self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(name),
                    size: s.size,
                    usage,
                    mapped_at_creation: false,
                });
                self.buffers.insert(name, buffer);
                self.generation += 1;
            }
            let mut bytes = s.bytes.clone();
            bytes.resize(s.size as usize, 0);
            self.ctx.queue.write_buffer(&self.buffers[name], 0, &bytes);
        }
        Ok(())
    }

    /// Records a copy of every state buffer but the per-step scratch ([`Self::with_per_step`])
    /// into the same-named buffer of `shadow` (made to match first): a checkpoint on the
    /// device that [`Self::copy_back`] restores.
    pub fn record_checkpoint(&self, encoder: &mut wgpu::CommandEncoder, shadow: &mut BufferPool) {
        for (name, buffer) in self.checkpoint_buffers() {
            let fits = shadow
                .buffers
                .get(name)
                .is_some_and(|b| b.size() == buffer.size());
            if !fits {
                let copy = self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(name),
                    size: buffer.size(),
                    usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                shadow.buffers.insert(name, copy);
            }
            encoder.copy_buffer_to_buffer(buffer, 0, &shadow.buffers[name], 0, buffer.size());
        }
    }

    /// Records the copy of `shadow`'s checkpoint back into this pool's buffers. A buffer
    /// allocated or grown since the checkpoint (whose earlier contents the checkpoint does not
    /// hold at its size) is cleared instead: a new buffer starts zeroed, and the step that
    /// grew it would find it so again. The per-step scratch keeps what the undone step left
    /// (and its size): the next step rewrites it before reading it, but a host read of it
    /// before that step (e.g. `GpuSolver::read_constraints`) sees the undone step's values.
    pub fn copy_back(&self, encoder: &mut wgpu::CommandEncoder, shadow: &BufferPool) {
        for (name, buffer) in self.checkpoint_buffers() {
            match shadow.buffers.get(name) {
                Some(saved) if saved.size() == buffer.size() => {
                    encoder.copy_buffer_to_buffer(saved, 0, buffer, 0, buffer.size());
                }
                _ => encoder.clear_buffer(buffer, 0, None),
            }
        }
    }
}
