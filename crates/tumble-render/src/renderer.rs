//! [`Renderer`]: the pipelines, the offscreen targets, and one frame from world to [`Image`].

use tumble::World;
use tumble::gpu::GpuContext;
use tumble::nalgebra::Matrix4;
use tumble::{Point3, Vec3};

use crate::bodies::{BodyBuffers, FrameBuffers, MAX_POINTS};
pub use crate::config::{Overlay, RenderConfig};
use crate::pipelines::{
    COLOUR_FORMAT, DEPTH_FORMAT, PipelineMaker, padded_row, render_source, storage_entry, texture,
};
use crate::{Camera, GRAPH_COLOUR_SLOTS, Image, RenderError, graph_colour};

pub use crate::bodies::Source;

/// Vertices of one box: 6 faces of 2 triangles.
const BOX_VERTICES: u32 = 36;
/// Vertices of one AABB outline: 12 edges of 2 ends.
const AABB_VERTICES: u32 = 24;
/// Direction towards the light: above, front left.
const LIGHT_DIRECTION: [f32; 3] = [-0.35, 1.0, 0.45];

/// The uniform block `Frame` of render.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct FrameUniform {
    view_proj: [f32; 16],
    light_view_proj: [f32; 16],
    light_dir: [f32; 4],
    viewport: [f32; 4],
    flags: [u32; 4],
}

fn matrix(m: &Matrix4<f32>) -> [f32; 16] {
    let mut out = [0.0; 16];
    out.copy_from_slice(m.as_slice());
    out
}

/// Draws worlds into an offscreen picture of a fixed size on one device.
#[derive(Debug)]
pub struct Renderer {
    ctx: GpuContext,
    config: RenderConfig,
    frame_layout: wgpu::BindGroupLayout,
    shadow_group: wgpu::BindGroup,
    box_pipeline: wgpu::RenderPipeline,
    shadow_pipeline: wgpu::RenderPipeline,
    dot_pipeline: wgpu::RenderPipeline,
    normal_pipeline: wgpu::RenderPipeline,
    aabb_pipeline: wgpu::RenderPipeline,
    pair_pipeline: wgpu::RenderPipeline,
    /// The fill of each graph colour's dots (`GRAPH_COLOUR_SLOTS` `vec4`s).
    graph_colours: wgpu::Buffer,
    /// The multisampled target (with more than one sample), resolved into `colour`.
    msaa: Option<wgpu::TextureView>,
    colour: wgpu::Texture,
    depth: wgpu::TextureView,
    shadow: wgpu::TextureView,
    uniform: wgpu::Buffer,
    readback: wgpu::Buffer,
    bodies: BodyBuffers,
    last_source: Option<Source>,
    /// Drawn into every picture by [`crate::status::draw`], when set.
    status_line: Option<String>,
}

impl Renderer {
    /// A renderer of `config`'s pictures on `ctx`'s device. To draw a `Backend::Gpu` world
    /// from its own buffers, use its device ([`World::gpu_context`], or
    /// [`Renderer::for_world`]); on another device the renderer reads the world on the host.
    pub fn new(ctx: &GpuContext, config: RenderConfig) -> Result<Self, RenderError> {
        config.validate(ctx)?;
        let device = &ctx.device;
        let (source, shared) = render_source()?;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("tumble-render"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let mut entries = vec![wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }];
        entries.extend((1..=7).map(storage_entry));
        entries.push(wgpu::BindGroupLayoutEntry {
            binding: 8,
            ..entries[0]
        });
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("render frame"),
            entries: &entries,
        });
        let shadow_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("render shadow map"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
            ],
        });
        let make_layout = |groups: &[Option<&wgpu::BindGroupLayout>]| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("render"),
                bind_group_layouts: groups,
                immediate_size: 0,
            })
        };
        let mut constants = config.palette.constants();
        constants.extend(shared);
        let main = PipelineMaker {
            ctx,
            module: module.clone(),
            layout: make_layout(&[Some(&frame_layout), Some(&shadow_layout)]),
            constants: constants.clone(),
        };
        let shadow_maker = PipelineMaker {
            ctx,
            module,
            layout: make_layout(&[Some(&frame_layout)]),
            constants,
        };
        use wgpu::CompareFunction::{Always, Less};
        use wgpu::PrimitiveTopology::{LineList, TriangleList};
        let s = config.samples;
        // The frame's pipelines: label, entry points, primitives, (depth write, depth test).
        let [
            box_pipeline,
            dot_pipeline,
            normal_pipeline,
            aabb_pipeline,
            pair_pipeline,
        ] = [
            (
                "render boxes",
                ("vs_box", Some("fs_box")),
                TriangleList,
                (true, Less),
            ),
            (
                "render dots",
                ("vs_dot", Some("fs_dot")),
                TriangleList,
                (false, Always),
            ),
            (
                "render normals",
                ("vs_normal", Some("fs_normal")),
                LineList,
                (false, Always),
            ),
            (
                "render aabbs",
                ("vs_aabb", Some("fs_aabb")),
                LineList,
                (false, Always),
            ),
            (
                "render pairs",
                ("vs_pair", Some("fs_pair")),
                LineList,
                (false, Always),
            ),
        ]
        .map(|(label, entries, topology, depth)| main.make(label, entries, topology, depth, s));
        let shadow_pipeline = shadow_maker.make(
            "render shadow map",
            ("vs_shadow", None),
            TriangleList,
            (true, Less),
            1,
        );

        let size = (config.width, config.height);
        let target = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let colour = texture(
            ctx,
            "render colour",
            size,
            1,
            COLOUR_FORMAT,
            target | wgpu::TextureUsages::COPY_SRC,
        );
        let msaa = (config.samples > 1).then(|| {
            texture(
                ctx,
                "render msaa",
                size,
                config.samples,
                COLOUR_FORMAT,
                target,
            )
            .create_view(&Default::default())
        });
        let depth = texture(
            ctx,
            "render depth",
            size,
            config.samples,
            DEPTH_FORMAT,
            target,
        )
        .create_view(&Default::default());
        let side = config.shadow_map_size.max(1);
        let shadow = texture(
            ctx,
            "render shadow map",
            (side, side),
            1,
            DEPTH_FORMAT,
            target | wgpu::TextureUsages::TEXTURE_BINDING,
        )
        .create_view(&Default::default());
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("render shadow sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let shadow_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("render shadow map"),
            layout: &shadow_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&shadow),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&sampler),
                },
            ],
        });
        let uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("render frame"),
            size: std::mem::size_of::<FrameUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let table: Vec<[f32; 4]> = (0..GRAPH_COLOUR_SLOTS as u32)
            .map(|c| {
                let [r, g, b] = graph_colour(c).unwrap_or([0.0; 3]);
                [r, g, b, 1.0]
            })
            .collect();
        let graph_colours = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("render graph colour table"),
            size: std::mem::size_of_val(&table[..]) as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        ctx.queue
            .write_buffer(&graph_colours, 0, bytemuck::cast_slice(&table));
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("render readback"),
            size: u64::from(padded_row(config.width)) * u64::from(config.height),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(Self {
            ctx: ctx.clone(),
            config,
            frame_layout,
            shadow_group,
            box_pipeline,
            shadow_pipeline,
            dot_pipeline,
            normal_pipeline,
            aabb_pipeline,
            pair_pipeline,
            graph_colours,
            msaa,
            colour,
            depth,
            shadow,
            uniform,
            readback,
            bodies: BodyBuffers::new(ctx),
            last_source: None,
            status_line: None,
        })
    }

    /// A renderer on the device of `world` when it runs on `Backend::Gpu` (so that its
    /// buffers are drawn as they are), or on a device of its own otherwise.
    pub fn for_world(world: &World, config: RenderConfig) -> Result<Self, RenderError> {
        let ctx = match world.gpu_context() {
            Some(ctx) => ctx,
            None => GpuContext::new().map_err(|e| RenderError::Gpu(e.to_string()))?,
        };
        Self::new(&ctx, config)
    }

    /// The device the renderer draws on.
    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// The settings.
    pub fn config(&self) -> &RenderConfig {
        &self.config
    }

    /// Where the last frame's bodies came from (`None` before the first frame).
    pub fn last_source(&self) -> Option<Source> {
        self.last_source
    }

    /// Sets the text drawn on a dark band into the top left corner of every picture from
    /// now on ([`crate::status`]); `None` (the default) draws none. An `Err` names a line
    /// that is empty, has characters other than printable ASCII and `'\n'`, or does not fit
    /// the picture, and keeps the line as it was.
    pub fn set_status_line(&mut self, line: Option<String>) -> Result<(), RenderError> {
        if let Some(text) = &line {
            crate::status::validate(text, self.config.width, self.config.height)?;
        }
        self.status_line = line;
        Ok(())
    }

    /// The status line drawn into the pictures, if any.
    pub fn status_line(&self) -> Option<&str> {
        self.status_line.as_deref()
    }

    /// The aspect ratio of the pictures (width over height).
    pub fn aspect(&self) -> f32 {
        self.config.width as f32 / self.config.height as f32
    }

    /// The light's orthographic view of the sphere the camera looks at.
    fn light_view_projection(&self, camera: &Camera) -> Matrix4<f32> {
        let radius = camera.view_radius(self.aspect()) * 1.3;
        let dir = Vec3::from(LIGHT_DIRECTION).normalize();
        let eye: Point3 = camera.target + dir * radius * 3.0;
        let view = Matrix4::look_at_rh(&eye, &camera.target, &Vec3::y());
        let (near, far) = (0.0, radius * 6.0);
        let mut ortho = Matrix4::identity();
        ortho[(0, 0)] = 1.0 / radius;
        ortho[(1, 1)] = 1.0 / radius;
        ortho[(2, 2)] = 1.0 / (near - far);
        ortho[(2, 3)] = near / (near - far);
        ortho * view
    }

    fn frame_group(&self, b: &FrameBuffers) -> wgpu::BindGroup {
        let buffers = [
            &self.uniform,
            &b.poses,
            &b.shapes,
            &b.kinds,
            &b.work,
            &b.manifolds,
            &b.contacts,
            &b.colors,
            &self.graph_colours,
        ];
        let entries: Vec<wgpu::BindGroupEntry> = buffers
            .iter()
            .enumerate()
            .map(|(i, buffer)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: buffer.as_entire_binding(),
            })
            .collect();
        self.ctx
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("render frame"),
                layout: &self.frame_layout,
                entries: &entries,
            })
    }

    /// Draws `world` as `camera` sees it, with `overlay`, and returns the picture. On
    /// `Backend::Gpu` (on the world's device) the draw is queued after the world's last step
    /// and reads its buffers; elsewhere it reads the poses on the host and uploads them.
    pub fn render(
        &mut self,
        world: &World,
        camera: &Camera,
        overlay: &Overlay,
    ) -> Result<Image, RenderError> {
        let buffers =
            self.bodies
                .prepare(&self.ctx, world, overlay.reads_manifolds(), overlay.pairs)?;
        self.last_source = Some(buffers.source);
        let shadows = self.config.shadow_map_size > 0;
        let dir = Vec3::from(LIGHT_DIRECTION).normalize();
        let uniform = FrameUniform {
            view_proj: matrix(&camera.view_projection(self.aspect())),
            light_view_proj: matrix(&self.light_view_projection(camera)),
            light_dir: [dir.x, dir.y, dir.z, if shadows { 1.0 } else { 0.0 }],
            viewport: [
                self.config.width as f32,
                self.config.height as f32,
                overlay.dot_radius,
                overlay.normal_length,
            ],
            flags: [
                u32::from(overlay.colors && buffers.has_colors),
                u32::from(buffers.pair_base.is_some()),
                buffers.pair_base.unwrap_or(0),
                buffers.pair_slots,
            ],
        };
        self.ctx
            .queue
            .write_buffer(&self.uniform, 0, bytemuck::bytes_of(&uniform));
        let group = self.frame_group(&buffers);
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        let depth_clear = |view| wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        };
        if shadows && buffers.bodies > 0 {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("render shadow map"),
                color_attachments: &[],
                depth_stencil_attachment: Some(depth_clear(&self.shadow)),
                ..Default::default()
            });
            pass.set_pipeline(&self.shadow_pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..BOX_VERTICES, 0..buffers.bodies);
        }
        let colour_view = self.colour.create_view(&Default::default());
        let [r, g, b] = self.config.palette.background.map(f64::from);
        {
            let (view, resolve) = match &self.msaa {
                Some(msaa) => (msaa, Some(&colour_view)),
                None => (&colour_view, None),
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("render picture"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: resolve,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a: 1.0 }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(depth_clear(&self.depth)),
                ..Default::default()
            });
            pass.set_bind_group(0, &group, &[]);
            pass.set_bind_group(1, &self.shadow_group, &[]);
            if buffers.bodies > 0 {
                pass.set_pipeline(&self.box_pipeline);
                pass.draw(0..BOX_VERTICES, 0..buffers.bodies);
            }
            if overlay.aabbs && buffers.bodies > 0 {
                pass.set_pipeline(&self.aabb_pipeline);
                pass.draw(0..AABB_VERTICES, 0..buffers.bodies);
            }
            if overlay.pairs && buffers.pair_slots > 0 {
                pass.set_pipeline(&self.pair_pipeline);
                pass.draw(0..2, 0..buffers.pair_slots);
            }
            let points = buffers.manifold_slots * MAX_POINTS as u32;
            if overlay.normals && points > 0 {
                pass.set_pipeline(&self.normal_pipeline);
                pass.draw(0..2, 0..points);
            }
            if (overlay.contacts || overlay.colors) && points > 0 {
                pass.set_pipeline(&self.dot_pipeline);
                pass.draw(0..6, 0..points);
            }
        }
        let (width, height) = (self.config.width, self.config.height);
        encoder.copy_texture_to_buffer(
            self.colour.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row(width)),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        self.ctx.queue.submit([encoder.finish()]);
        let mut image = self.read_picture()?;
        if let Some(text) = &self.status_line {
            crate::status::draw(&mut image, text)?;
        }
        Ok(image)
    }

    /// Waits for the frame and copies it out of the readback buffer, row by row.
    fn read_picture(&self) -> Result<Image, RenderError> {
        let gpu = |e: &dyn std::fmt::Display| RenderError::Gpu(e.to_string());
        self.readback.map_async(wgpu::MapMode::Read, .., |_| {});
        self.ctx.wait_idle().map_err(|e| gpu(&e))?;
        let (width, height) = (self.config.width as usize, self.config.height as usize);
        let row = padded_row(self.config.width) as usize;
        let mut pixels = Vec::with_capacity(width * height * 4);
        {
            let view = self.readback.get_mapped_range(..).map_err(|e| gpu(&e))?;
            for y in 0..height {
                pixels.extend_from_slice(&view[y * row..y * row + width * 4]);
            }
        }
        self.readback.unmap();
        Ok(Image {
            width: self.config.width,
            height: self.config.height,
            pixels,
        })
    }
}
