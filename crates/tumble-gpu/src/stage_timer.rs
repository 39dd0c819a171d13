//! Per-stage GPU time from timestamp queries written at the start and end of each compute
//! pass. Every stage records into its own pass, so the timings need only the
//! `TIMESTAMP_QUERY` feature (not timestamps inside passes). Without the feature the timer
//! records nothing and reports nothing.

use crate::{GpuContext, GpuError};

/// The most stages one timer holds (two queries each); enough for a full step.
pub const MAX_TIMED_STAGES: u32 = 64;

/// Opens compute passes, one per stage, with timestamps when the device has them.
#[derive(Debug)]
pub struct StageTimer {
    ctx: GpuContext,
    queries: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
    names: Vec<&'static str>,
}

impl StageTimer {
    /// A timer on `ctx`; inert when the device lacks timestamp queries.
    pub fn new(ctx: &GpuContext) -> Self {
        let queries = ctx.has_timestamps.then(|| {
            let count = 2 * MAX_TIMED_STAGES;
            let bytes = u64::from(count) * u64::from(wgpu::QUERY_SIZE);
            let set = ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("stage timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count,
            });
            let resolve = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("stage timestamps resolve"),
                size: bytes,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let staging = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("stage timestamps staging"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            (set, resolve, staging)
        });
        Self {
            ctx: ctx.clone(),
            queries,
            names: Vec::new(),
        }
    }

    /// A timer that never measures (for callers that do not want timings).
    pub fn disabled(ctx: &GpuContext) -> Self {
        Self {
            ctx: ctx.clone(),
            queries: None,
            names: Vec::new(),
        }
    }

    /// True when this timer writes timestamps.
    pub fn is_enabled(&self) -> bool {
        self.queries.is_some()
    }

    /// Opens a compute pass for stage `name`, timed when possible.
    pub fn begin_pass<'e>(
        &mut self,
        encoder: &'e mut wgpu::CommandEncoder,
        name: &'static str,
    ) -> wgpu::ComputePass<'e> {
        let index = self.names.len() as u32;
        let timestamp_writes = match &self.queries {
            Some((set, _, _)) if index < MAX_TIMED_STAGES => {
                self.names.push(name);
                Some(wgpu::ComputePassTimestampWrites {
                    query_set: set,
                    beginning_of_pass_write_index: Some(2 * index),
                    end_of_pass_write_index: Some(2 * index + 1),
                })
            }
            _ => None,
        };
        encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(name),
            timestamp_writes,
        })
    }

    /// Records the resolve of this frame's timestamps; call once, after the last pass.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some((set, resolve, staging)) = &self.queries
            && !self.names.is_empty()
        {
            let count = 2 * self.names.len() as u32;
            encoder.resolve_query_set(set, 0..count, resolve, 0);
            let bytes = u64::from(count) * u64::from(wgpu::QUERY_SIZE);
            encoder.copy_buffer_to_buffer(resolve, 0, staging, 0, bytes);
        }
    }

    /// Waits for the submitted frame and returns each stage's GPU time in seconds (stages
    /// timed twice, e.g. per substep, are summed), then starts a new frame.
    pub fn read(&mut self) -> Result<Vec<(&'static str, f64)>, GpuError> {
        let names = std::mem::take(&mut self.names);
        let Some((_, _, staging)) = &self.queries else {
            return Ok(Vec::new());
        };
        if names.is_empty() {
            return Ok(Vec::new());
        }
        let bytes = 2 * names.len() as u64 * u64::from(wgpu::QUERY_SIZE);
        staging.map_async(wgpu::MapMode::Read, 0..bytes, |_| {});
        self.ctx.wait_idle()?;
        let ticks: Vec<u64> = {
            let view = staging
                .get_mapped_range(0..bytes)
                .map_err(|e| GpuError::Device(e.to_string()))?;
            bytemuck::pod_collect_to_vec(&view)
        };
        staging.unmap();
        let period_s = f64::from(self.ctx.queue.get_timestamp_period()) * 1e-9;
        let mut out: Vec<(&'static str, f64)> = Vec::new();
        for (i, name) in names.iter().enumerate() {
            let dt = ticks[2 * i + 1].saturating_sub(ticks[2 * i]) as f64 * period_s;
            match out.iter_mut().find(|(n, _)| n == name) {
                Some((_, total)) => *total += dt,
                None => out.push((name, dt)),
            }
        }
        Ok(out)
    }

    /// Forgets the stages recorded so far (for a frame that was never submitted).
    pub fn reset(&mut self) {
        self.names.clear();
    }
}
