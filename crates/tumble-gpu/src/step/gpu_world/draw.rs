//! The buffers a renderer binds to draw a [`GpuWorld`] as its last step left it, with nothing
//! read back to the host.

use super::*;

/// The GPU buffers that describe a world's bodies and last step's contacts, for drawing.
///
/// Each is a handle to the world's own buffer (cloning a `wgpu::Buffer` shares it), all with
/// `STORAGE` usage, valid until bodies are added or removed or the pair buffers grow (take
/// them again before each frame). A draw submitted on the world's queue after a step sees
/// that step's results.
#[derive(Clone, Debug)]
pub struct DrawBuffers {
    /// Bodies in the world; the per-body arrays hold at least this many records.
    pub body_count: u32,
    /// `array<GpuPose>`, one per body.
    pub poses: wgpu::Buffer,
    /// `array<GpuShape>`, one per body: half extents, and `BODY_STATIC` for bodies contacts
    /// cannot move (fixed, kinematic and sleeping ones).
    pub shapes: wgpu::Buffer,
    /// The manifolds' `WorkList`: its `count` is the number of manifold slots in use.
    pub contact_work: wgpu::Buffer,
    /// `array<GpuManifold>`, one per slot (`len == 0` when not in contact).
    pub manifolds: wgpu::Buffer,
    /// `array<GpuContact>`, `MAX_MANIFOLD_POINTS` per manifold slot.
    pub contacts: wgpu::Buffer,
    /// Manifold slots in `manifolds` (the most `contact_work.count` can be).
    pub manifold_capacity: u32,
}

impl GpuWorld {
    /// The buffers holding the bodies' poses and shapes and the last step's manifolds, for a
    /// renderer on this world's device ([`GpuWorld::context`]). `None` before any body was
    /// uploaded.
    pub fn draw_buffers(&self) -> Option<DrawBuffers> {
        if self.bodies.is_empty() {
            return None;
        }
        let b = self.collision.buffers(self.pool.get(BODIES));
        let (manifolds, contacts, contact_work, manifold_capacity) = self.contact_buffers();
        Some(DrawBuffers {
            body_count: self.bodies.len() as u32,
            poses: b.poses.clone(),
            shapes: b.shapes.clone(),
            contact_work,
            manifolds,
            contacts,
            manifold_capacity,
        })
    }
}
