//! The pieces the renderer is built from: bind group entries, textures, the pipelines of
//! render.wgsl and the shader source composed with the GPU step's layout.

use tumble::gpu::GpuContext;

use crate::RenderError;

pub(crate) const COLOUR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

pub(crate) fn storage_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
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

pub(crate) fn texture(
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
pub(crate) fn padded_row(width: u32) -> u32 {
    let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    (width * 4).div_ceil(align) * align
}

/// The pipelines of one module, sharing a layout and the palette's constants.
pub(crate) struct PipelineMaker<'a> {
    pub ctx: &'a GpuContext,
    pub module: wgpu::ShaderModule,
    pub layout: wgpu::PipelineLayout,
    pub constants: Vec<(&'static str, f64)>,
}

impl PipelineMaker<'_> {
    pub(crate) fn make(
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

/// Pipeline `override` values by name.
pub(crate) type Overrides = Vec<(&'static str, f64)>;

/// render.wgsl after shaders/common/layout.wgsl and what it requires, and the values of the
/// tumble-gpu `override` constants the whole declares (the shared ones and the body kinds),
/// defined once in tumble-gpu as for every kernel.
pub(crate) fn render_source() -> Result<(String, Overrides), RenderError> {
    let layout = tumble::gpu::shader::ShaderSource::of_path("common/layout.wgsl")
        .map_err(|e| RenderError::Gpu(e.to_string()))?
        .compose();
    let source = format!(
        "{layout}\nconst GRAPH_COLOUR_SLOTS: u32 = {}u;\n{}",
        crate::GRAPH_COLOUR_SLOTS,
        include_str!("render.wgsl")
    );
    let shared = tumble::gpu::constants::shader_constants()
        .into_iter()
        .chain(tumble::gpu::solver::constants::solver_constants())
        .filter(|(name, _)| source.contains(&format!("override {name}:")))
        .collect();
    Ok((source, shared))
}
