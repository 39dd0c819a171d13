//! [`Renderer`]: the pipelines, the offscreen targets, and one frame from world to [`Image`].

use tumble::World;
use tumble::gpu::GpuContext;
use tumble::nalgebra::Matrix4;
use tumble::{Point3, Vec3};

use crate::bodies::{BodyBuffers, FrameBuffers, MAX_POINTS};
pub use crate::config::{Overlay, RenderConfig};
use crate::{Camera, Image, RenderError};

pub use crate::bodies::Source;

const COLOUR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Vertices of one box: 6 faces of 2 triangles.
const BOX_VERTICES: u32 = 36;
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
    /// The multisampled target (with more than one sample), resolved into `colour`.
    msaa: Option<wgpu::TextureView>,
    colour: wgpu::Texture,
    depth: wgpu::TextureView,
    shadow: wgpu::TextureView,
    uniform: wgpu::Buffer,
    readback: wgpu::Buffer,
    bodies: BodyBuffers,
    last_source: Option<Source>,
}

fn storage_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn texture(
    ctx: &GpuContext,
    label: &str,
    (width, height): (u32, u32),
    samples: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// Bytes per row of the readback buffer: the picture's row, padded as copies require.
fn padded_row(width: u32) -> u32 {
    let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    (width * 4).div_ceil(align) * align
}

/// The pipelines of one module, sharing a layout and the palette's constants.
struct PipelineMaker<'a> {
    ctx: &'a GpuContext,
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    constants: Vec<(&'static str, f64)>,
}

impl PipelineMaker<'_> {
    fn make(
        &self,
        label: &str,
        (vs, fs): (&str, Option<&str>),
        topology: wgpu::PrimitiveTopology,
        depth: (bool, wgpu::CompareFunction),
        samples: u32,
    ) -> wgpu::RenderPipeline {
        let options = wgpu::PipelineCompilationOptions {
            constants: &self.constants,
            zero_initialize_workgroup_memory: false,
        };
        let targets = [Some(wgpu::ColorTargetState {
            format: COLOUR_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })];
        self.ctx
            .device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&self.layout),
                vertex: wgpu::VertexState {
                    module: &self.module,
                    entry_point: Some(vs),
                    compilation_options: options.clone(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(depth.0),
                    depth_compare: Some(depth.1),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: samples,
                    ..Default::default()
                },
                fragment: fs.map(|fs| wgpu::FragmentState {
                    module: &self.module,
                    entry_point: Some(fs),
                    compilation_options: options,
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
    }
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
        entries.extend((1..=6).map(storage_entry));
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
        let [box_pipeline, dot_pipeline, normal_pipeline] = [
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
            msaa,
            colour,
            depth,
            shadow,
            uniform,
            readback,
            bodies: BodyBuffers::new(ctx),
            last_source: None,
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
        let wants_contacts = overlay.contacts || overlay.normals;
        let buffers = self.bodies.prepare(&self.ctx, world, wants_contacts)?;
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
            let points = buffers.manifold_slots * MAX_POINTS as u32;
            if overlay.normals && points > 0 {
                pass.set_pipeline(&self.normal_pipeline);
                pass.draw(0..2, 0..points);
            }
            if overlay.contacts && points > 0 {
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
        self.read_picture()
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

/// Pipeline `override` values by name.
type Overrides = Vec<(&'static str, f64)>;

/// render.wgsl after shaders/common/layout.wgsl and what it requires, and the values of the
/// tumble-gpu `override` constants the whole declares (the shared ones and the body kinds),
/// defined once in tumble-gpu as for every kernel.
fn render_source() -> Result<(String, Overrides), RenderError> {
    let layout = tumble::gpu::shader::ShaderSource::of_path("common/layout.wgsl")
        .map_err(|e| RenderError::Gpu(e.to_string()))?
        .compose();
    let source = format!("{layout}\n{}", include_str!("render.wgsl"));
    let shared = tumble::gpu::constants::shader_constants()
        .into_iter()
        .chain(tumble::gpu::solver::constants::solver_constants())
        .filter(|(name, _)| source.contains(&format!("override {name}:")))
        .collect();
    Ok((source, shared))
}
