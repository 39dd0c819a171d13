//! [`GpuWorld`]'s contact summary: the step's contact counts reduced on the GPU
//! (`contact_summary`), for a host that wants the counts without the manifolds.

use super::*;
use crate::kernel::Kernel;
use crate::kernels::contact_summary::{
    CONTACT_SUMMARY, CONTACT_SUMMARY_BYTES, CONTACT_SUMMARY_WORDS, ContactSummary,
};

/// The summary kernel and its 32-byte output, made on the first request.
#[derive(Debug)]
pub(super) struct SummaryStage {
    kernel: Kernel,
    output: wgpu::Buffer,
}

impl GpuWorld {
    /// Records the summary of the last step's manifolds into its output buffer (cleared
    /// first) and returns that buffer.
    pub(super) fn record_summary(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<wgpu::Buffer, GpuError> {
        if self.summary.is_none() {
            let kernel = Kernel::new(&self.ctx, &CONTACT_SUMMARY)?;
            let output = self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("contact summary"),
                size: CONTACT_SUMMARY_BYTES,
                usage: STORAGE_USAGE,
                mapped_at_creation: false,
            });
            self.summary = Some(SummaryStage { kernel, output });
        }
        let (manifolds, contacts, work, _) = self.contact_buffers();
        let stage = self.summary.as_ref().expect("made above");
        let group = stage.kernel.bind_named(&self.ctx, |name| match name {
            "work" => &work,
            "manifolds" => &manifolds,
            "contacts" => &contacts,
            _ => &stage.output,
        });
        encoder.clear_buffer(&stage.output, 0, None);
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("contact_summary"),
                timestamp_writes: None,
            });
            stage.kernel.dispatch_work(&mut pass, &group, &work);
        }
        Ok(stage.output.clone())
    }

    /// The last step's contact summary, read now (blocking); `None` before the first step.
    pub(super) fn read_summary_now(&mut self) -> Result<Option<ContactSummary>, GpuError> {
        if self.steps == 0 {
            return Ok(None);
        }
        let mut encoder = self.ctx.encoder("tumble contact summary");
        let output = self.record_summary(&mut encoder)?;
        self.ctx.submit(encoder)?;
        let words: Vec<u32> = self
            .ctx
            .read_buffer(&output, 0, CONTACT_SUMMARY_WORDS as u64)?;
        self.bytes_read += CONTACT_SUMMARY_BYTES;
        let mut out = [0; CONTACT_SUMMARY_WORDS];
        out.copy_from_slice(&words);
        Ok(Some(ContactSummary::from_words(out)))
    }
}
