//! Access to a `Backend::Gpu` world's buffers for drawing it where its state lives.

use tumble_gpu::GpuContext;
use tumble_gpu::step::DrawBuffers;

use crate::World;

impl World {
    /// On `Backend::Gpu`: the device holding the world and the buffers of its bodies' poses
    /// and shapes and of the last step's manifolds, in dense order (the order of
    /// [`World::handles`]), for a renderer to bind without reading anything back. A draw
    /// submitted on `context.queue` after a step sees that step's results; poses set since
    /// the last step reach these buffers with the next step.
    ///
    /// `None` on the other backends (their state lives on the host: read it with
    /// [`World::pose`]) and before the first step has uploaded the bodies.
    pub fn gpu_draw_buffers(&self) -> Option<(GpuContext, DrawBuffers)> {
        self.backend.draw_buffers()
    }

    /// On `Backend::Gpu`: the device holding the world (from its creation on), the one a
    /// renderer must use to bind [`World::gpu_draw_buffers`]. `None` on the other backends.
    pub fn gpu_context(&self) -> Option<GpuContext> {
        self.backend.gpu_context()
    }

    /// On `Backend::Gpu`: the buffer of last step's graph colors, one `ColorSlot` (8 bytes:
    /// the color, then a proposal nothing outside the step reads) per manifold slot of
    /// [`World::gpu_draw_buffers`]' `manifolds`. A color below
    /// [`crate::solver::GRAPH_COLOR_COUNT`] is a graph color, [`crate::solver::OVERFLOW_COLOR`]
    /// the overflow set; other values mark slots without points. `None` on the other
    /// backends ([`World::contact_colors`] holds theirs) and before the first step.
    pub fn gpu_contact_colors(&self) -> Option<crate::gpu::wgpu::Buffer> {
        self.backend.color_buffer()
    }
}
