//! What a frame draws from: the world's own GPU buffers on `Backend::Gpu`, or the renderer's
//! buffers filled from the host (one upload of every pose per frame) elsewhere.

use std::collections::HashMap;

use tumble::gpu::GpuContext;
use tumble::gpu::layout::{BODY_STATIC, GpuContact, GpuManifold, GpuPose, GpuShape};
use tumble::gpu::step::DrawBuffers;
use tumble::solver::{EMPTY_COLOR, NO_COLOR};
use tumble::{BodyHandle, BodyKind, World};

use crate::RenderError;

/// Kind codes of the shader: the GPU step's own `GpuBody::kind` values (`BODY_*` overrides
/// in render.wgsl).
fn kind_code(kind: BodyKind) -> u32 {
    use tumble::gpu::solver::constants::{BODY_DYNAMIC, BODY_FIXED, BODY_KINEMATIC};
    match kind {
        BodyKind::Fixed => BODY_FIXED,
        BodyKind::Dynamic => BODY_DYNAMIC,
        BodyKind::Kinematic => BODY_KINEMATIC,
    }
}

/// Points per manifold slot in the contact arrays (`MAX_MANIFOLD_POINTS` in render.wgsl).
pub(crate) const MAX_POINTS: usize = tumble::gpu::MAX_MANIFOLD_POINTS as usize;

const USAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE.union(wgpu::BufferUsages::COPY_DST);

/// A storage buffer of the renderer's, grown (never shrunk) to what a frame needs.
#[derive(Debug)]
struct Grown {
    label: &'static str,
    buffer: wgpu::Buffer,
}

impl Grown {
    fn new(ctx: &GpuContext, label: &'static str) -> Self {
        Self {
            label,
            buffer: Self::make(ctx, label, 256),
        }
    }

    fn make(ctx: &GpuContext, label: &str, size: u64) -> wgpu::Buffer {
        ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: USAGE,
            mapped_at_creation: false,
        })
    }

    /// Writes `data` at the start of the buffer, growing it first when too small.
    fn write<T: bytemuck::Pod>(&mut self, ctx: &GpuContext, data: &[T]) {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        if bytes.len() as u64 > self.buffer.size() {
            let size = (bytes.len() as u64).next_power_of_two();
            self.buffer = Self::make(ctx, self.label, size);
        }
        if !bytes.is_empty() {
            ctx.queue.write_buffer(&self.buffer, 0, bytes);
        }
    }
}

/// Where a frame's boxes and contacts come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// The `Backend::Gpu` world's own buffers: nothing about the bodies was read back.
    WorldBuffers,
    /// Poses, shapes and contacts read on the host and uploaded once for the frame.
    Uploaded,
}

/// The buffers of one frame, ready to bind.
pub(crate) struct FrameBuffers {
    pub source: Source,
    pub bodies: u32,
    /// Manifold slots the contact overlays walk (`MAX_POINTS` instances each).
    pub manifold_slots: u32,
    /// Instances of the pair lines: the broad phase's candidate pairs.
    pub pair_slots: u32,
    /// Where the pair lines' bodies are: `None` in the manifold slots `0..work[0]` (on the
    /// GPU, where each slot is one candidate pair), or `Some(first)`: records
    /// `first..first + pair_slots` of `manifolds`, past the host's contact manifolds.
    pub pair_base: Option<u32>,
    pub poses: wgpu::Buffer,
    pub shapes: wgpu::Buffer,
    pub kinds: wgpu::Buffer,
    pub work: wgpu::Buffer,
    pub manifolds: wgpu::Buffer,
    pub contacts: wgpu::Buffer,
    /// `array<ColorSlot>` by manifold slot: the solver's graph colours.
    pub colors: wgpu::Buffer,
    /// Whether `colors` holds this frame's colours (not before the first step on the GPU).
    pub has_colors: bool,
}

/// The renderer's own buffers, and what it last uploaded of the kinds.
#[derive(Debug)]
pub(crate) struct BodyBuffers {
    poses: Grown,
    shapes: Grown,
    kinds: Grown,
    work: Grown,
    manifolds: Grown,
    contacts: Grown,
    colors: Grown,
    uploaded_kinds: Option<Vec<u32>>,
}

impl BodyBuffers {
    pub(crate) fn new(ctx: &GpuContext) -> Self {
        Self {
            poses: Grown::new(ctx, "render poses"),
            shapes: Grown::new(ctx, "render shapes"),
            kinds: Grown::new(ctx, "render kinds"),
            work: Grown::new(ctx, "render contact count"),
            manifolds: Grown::new(ctx, "render manifolds"),
            contacts: Grown::new(ctx, "render contact points"),
            colors: Grown::new(ctx, "render graph colours"),
            uploaded_kinds: None,
        }
    }

    /// Uploads the bodies' kinds when they differ from the last upload.
    fn write_kinds(&mut self, ctx: &GpuContext, world: &World) -> Result<(), RenderError> {
        let kinds = world
            .handles()
            .iter()
            .map(|&h| world.kind(h).map(kind_code))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| RenderError::World(e.to_string()))?;
        if self.uploaded_kinds.as_ref() != Some(&kinds) {
            self.kinds.write(ctx, &kinds);
            self.uploaded_kinds = Some(kinds);
        }
        Ok(())
    }

    /// The buffers to draw `world` from. `contacts`: whether an overlay needs the manifolds;
    /// `pairs`: whether it needs the broad phase's pairs.
    pub(crate) fn prepare(
        &mut self,
        ctx: &GpuContext,
        world: &World,
        contacts: bool,
        pairs: bool,
    ) -> Result<FrameBuffers, RenderError> {
        self.write_kinds(ctx, world)?;
        if let Some(draw) = world_buffers(ctx, world) {
            let gpu_colors = world.gpu_contact_colors();
            let has_colors = gpu_colors.is_some();
            return Ok(FrameBuffers {
                source: Source::WorldBuffers,
                bodies: draw.body_count,
                manifold_slots: if contacts { draw.manifold_capacity } else { 0 },
                pair_slots: if pairs { draw.manifold_capacity } else { 0 },
                pair_base: None,
                poses: draw.poses,
                shapes: draw.shapes,
                kinds: self.kinds.buffer.clone(),
                work: draw.contact_work,
                manifolds: draw.manifolds,
                contacts: draw.contacts,
                colors: gpu_colors.unwrap_or_else(|| self.colors.buffer.clone()),
                has_colors,
            });
        }
        let failed = |e: tumble::Error| RenderError::World(e.to_string());
        let mut poses = Vec::with_capacity(world.body_count());
        let mut shapes = Vec::with_capacity(world.body_count());
        for &h in world.handles() {
            poses.push(GpuPose::from_pose(&world.pose(h).map_err(failed)?));
            let half = world.half_extents(h).map_err(failed)?;
            // As the GPU step flags them: bodies that contacts cannot move, sleeping ones too.
            let still = world.kind(h).map_err(failed)? != BodyKind::Dynamic
                || world.is_sleeping(h).map_err(failed)?;
            shapes.push(GpuShape {
                hx: half.x,
                hy: half.y,
                hz: half.z,
                flags: if still { BODY_STATIC } else { 0 },
            });
        }
        self.poses.write(ctx, &poses);
        self.shapes.write(ctx, &shapes);
        let mut slots = 0;
        let mut pair_slots = 0;
        if contacts || pairs {
            let dense: HashMap<BodyHandle, u32> = (0u32..)
                .zip(world.handles())
                .map(|(i, &h)| (h, i))
                .collect();
            let reports = if contacts {
                world.contacts()
            } else {
                Vec::new()
            };
            let colours = world.contact_colors();
            let mut manifolds = vec![GpuManifold::default(); reports.len()];
            let mut points = vec![GpuContact::default(); reports.len() * MAX_POINTS];
            let mut colors = vec![[EMPTY_COLOR, NO_COLOR]; reports.len()];
            for (k, report) in reports.iter().enumerate() {
                let n = report.normal;
                manifolds[k].normal = [n.x, n.y, n.z, 0.0];
                manifolds[k].len = report.points.len().min(MAX_POINTS) as u32;
                // A body removed since the step has no index: its pair is drawn at body 0.
                manifolds[k].body_a = dense.get(&report.body_a).copied().unwrap_or(0);
                manifolds[k].body_b = dense.get(&report.body_b).copied().unwrap_or(0);
                for (p, point) in report.points.iter().take(MAX_POINTS).enumerate() {
                    let q = point.position;
                    points[k * MAX_POINTS + p].position = [q.x, q.y, q.z, 0.0];
                    points[k * MAX_POINTS + p].depth = point.depth;
                }
                if let Some(Some(c)) = colours.get(k) {
                    colors[k][0] = *c;
                }
            }
            slots = reports.len() as u32;
            // The broad phase's pairs follow the contact manifolds as records without
            // points, which only the pair lines read.
            if pairs {
                for &(a, b) in world.broad_phase_pairs() {
                    // A pair with a body removed since the step is not drawn.
                    if let (Some(&a), Some(&b)) = (dense.get(&a), dense.get(&b)) {
                        manifolds.push(GpuManifold {
                            body_a: a,
                            body_b: b,
                            ..Default::default()
                        });
                        pair_slots += 1;
                    }
                }
            }
            self.manifolds.write(ctx, &manifolds);
            self.contacts.write(ctx, &points);
            self.colors.write(ctx, &colors);
        }
        self.work.write(ctx, &[slots, 0, 0, 0]);
        Ok(FrameBuffers {
            source: Source::Uploaded,
            bodies: poses.len() as u32,
            manifold_slots: slots,
            pair_slots,
            pair_base: Some(slots),
            poses: self.poses.buffer.clone(),
            shapes: self.shapes.buffer.clone(),
            kinds: self.kinds.buffer.clone(),
            work: self.work.buffer.clone(),
            manifolds: self.manifolds.buffer.clone(),
            contacts: self.contacts.buffer.clone(),
            colors: self.colors.buffer.clone(),
            has_colors: true,
        })
    }
}

/// The world's own buffers, when it lives on this renderer's device and they hold its
/// current bodies (bodies added since the last step are drawn from the host instead).
fn world_buffers(ctx: &GpuContext, world: &World) -> Option<DrawBuffers> {
    let (world_ctx, draw) = world.gpu_draw_buffers()?;
    (world_ctx.device == ctx.device && draw.body_count as usize == world.body_count())
        .then_some(draw)
}
