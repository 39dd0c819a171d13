//! One compute kernel: its WGSL source, its declared buffer bindings, the pipeline built from
//! them, and dispatch helpers (direct, folded past the per-dimension limit, and indirect).
//!
//! Adding a kernel takes three pieces: a file in `shaders/` with one entry point `main`, a
//! [`KernelSpec`] listing the common files and bindings, and a typed argument struct of named
//! buffers implementing [`KernelArgs`] (in binding order). The spec is checked against the
//! shader's own declarations when the pipeline is built and in the layout test.

use crate::shader::{Binding, ShaderSource, override_names, reflect_bindings};
use crate::{GpuContext, GpuError, constants};

/// Everything needed to build a kernel's pipeline.
#[derive(Clone, Copy, Debug)]
pub struct KernelSpec {
    /// The kernel's name (the stage name it implements, used in labels and errors).
    pub name: &'static str,
    /// Its WGSL source.
    pub source: ShaderSource,
    /// Its buffers in binding order (group 0, binding = index).
    pub bindings: &'static [Binding],
}

impl KernelSpec {
    /// Parses and validates the shader and checks its bindings match [`Self::bindings`].
    pub fn check(&self) -> Result<naga::Module, GpuError> {
        let module = self.source.parse(self.name)?;
        let mut validator = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            crate::validation_capabilities(),
        );
        validator.validate(&module).map_err(|e| GpuError::Shader {
            shader: self.name,
            message: e.emit_to_string(&self.source.compose()),
        })?;
        let declared: Vec<(u32, u32, Binding)> = self
            .bindings
            .iter()
            .enumerate()
            .map(|(i, &b)| (0, i as u32, b))
            .collect();
        let found = reflect_bindings(&module);
        if found != declared {
            return Err(GpuError::Shader {
                shader: self.name,
                message: format!(
                    "bindings in the shader {found:?} differ from the kernel spec {declared:?}"
                ),
            });
        }
        Ok(module)
    }

    /// Like [`Self::check`], then specializes the module with the override values (plus
    /// `extra`) and validates the result again, as wgpu does when it builds the pipeline.
    pub fn check_specialized(
        &self,
        extra: &[(&'static str, f64)],
    ) -> Result<(naga::Module, naga::valid::ModuleInfo), GpuError> {
        let module = self.check()?;
        let fail = |message: String| GpuError::Shader {
            shader: self.name,
            message,
        };
        let info = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            crate::validation_capabilities(),
        )
        .validate(&module)
        .map_err(|e| fail(e.to_string()))?;
        let mut constants = naga::back::PipelineConstants::default();
        for (name, value) in self.override_values(&module, extra)? {
            constants.insert(name.to_string(), value);
        }
        let (specialized, info) = naga::back::pipeline_constants::process_overrides(
            &module,
            &info,
            Some((naga::ShaderStage::Compute, "main")),
            &constants,
        )
        .map_err(|e| fail(e.to_string()))?;
        Ok((specialized.into_owned(), info.into_owned()))
    }

    /// The override values for this kernel: the shared constants its module declares, then
    /// `extra` (specializations such as effect switches). Errs on a value the shader lacks.
    pub fn override_values(
        &self,
        module: &naga::Module,
        extra: &[(&'static str, f64)],
    ) -> Result<Vec<(&'static str, f64)>, GpuError> {
        let names = override_names(module);
        let mut values: Vec<(&'static str, f64)> = constants::shader_constants()
            .into_iter()
            .filter(|(n, _)| names.iter().any(|m| m == n))
            .collect();
        for &(name, value) in extra {
            if !names.iter().any(|m| m == name) {
                return Err(GpuError::Shader {
                    shader: self.name,
                    message: format!("no override named {name} to specialize"),
                });
            }
            values.retain(|(n, _)| *n != name);
            values.push((name, value));
        }
        Ok(values)
    }
}

/// A kernel's buffers as a typed struct of named fields; `buffers` lists them in binding order.
pub trait KernelArgs {
    /// The buffers, in the order of the kernel's [`KernelSpec::bindings`].
    fn buffers(&self) -> Vec<&wgpu::Buffer>;
}

/// A built kernel: compute pipeline plus the layout of its single bind group.
#[derive(Clone, Debug)]
pub struct Kernel {
    /// What it was built from.
    pub spec: &'static KernelSpec,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl Kernel {
    /// Builds the pipeline with the shared constants.
    pub fn new(ctx: &GpuContext, spec: &'static KernelSpec) -> Result<Self, GpuError> {
        Self::specialized(ctx, spec, &[])
    }

    /// Builds the pipeline with extra `override` values (effects compiled in or out).
    pub fn specialized(
        ctx: &GpuContext,
        spec: &'static KernelSpec,
        overrides: &[(&'static str, f64)],
    ) -> Result<Self, GpuError> {
        let module = spec.check()?;
        let constants = spec.override_values(&module, overrides)?;
        let device = &ctx.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(spec.name),
            source: wgpu::ShaderSource::Wgsl(spec.source.compose().into()),
        });
        let entries: Vec<wgpu::BindGroupLayoutEntry> = spec
            .bindings
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupLayoutEntry {
                binding: i as u32,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: match b {
                        Binding::Uniform => wgpu::BufferBindingType::Uniform,
                        Binding::StorageRead => {
                            wgpu::BufferBindingType::Storage { read_only: true }
                        }
                        Binding::StorageReadWrite => {
                            wgpu::BufferBindingType::Storage { read_only: false }
                        }
                    },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(spec.name),
            entries: &entries,
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(spec.name),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(spec.name),
            layout: Some(&pipeline_layout),
            module: &shader,
            entry_point: Some("main"),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &constants,
                zero_initialize_workgroup_memory: true,
            },
            cache: None,
        });
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Shader {
                shader: spec.name,
                message: error.to_string(),
            });
        }
        Ok(Self {
            spec,
            pipeline,
            layout,
        })
    }

    /// A bind group over `args` (whole buffers).
    pub fn bind(&self, ctx: &GpuContext, args: &dyn KernelArgs) -> wgpu::BindGroup {
        let buffers = args.buffers();
        assert_eq!(
            buffers.len(),
            self.spec.bindings.len(),
            "kernel {} takes {} buffers",
            self.spec.name,
            self.spec.bindings.len()
        );
        let entries: Vec<wgpu::BindGroupEntry> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.spec.name),
            layout: &self.layout,
            entries: &entries,
        })
    }

    /// Dispatches enough workgroups for `threads` threads (no-op for zero).
    pub fn dispatch(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        threads: u32,
    ) {
        let (x, y) = constants::workgroups_for(threads);
        self.dispatch_workgroups(pass, group, x, y);
    }

    /// Dispatches an explicit `x * y` grid of workgroups.
    pub fn dispatch_workgroups(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        x: u32,
        y: u32,
    ) {
        if x == 0 || y == 0 {
            return;
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups(x, y, 1);
    }

    /// Dispatches with workgroup counts read on the GPU from `args` at byte `offset`
    /// (three `u32`: x, y, z), so a count produced by an earlier kernel never visits the CPU.
    pub fn dispatch_indirect(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        args: &wgpu::Buffer,
        offset: u64,
    ) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.dispatch_workgroups_indirect(args, offset);
    }
}
