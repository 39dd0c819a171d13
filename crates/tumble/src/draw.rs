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
}
