//! One compute kernel: its WGSL file, the pipeline built from it (once per device and
//! override values, in one cache), bind groups by binding name, and dispatch helpers (direct,
//! folded past the per-dimension limit, and indirect).
//!
//! # Adding a kernel
//!
//! A kernel is a file in `shaders/` with one entry point `main`, whose first lines name the
//! shared files it needs (see [`crate::shader`]), plus one [`KernelSpec`] static:
//!
//! ```ignore
//! // shaders/match_pairs.wgsl
//! // requires: common/indexing.wgsl common/layout.wgsl
//! // This step's pair WorkList.
//! @group(0) @binding(0) var<storage, read> work: WorkList;
//! // Output: last step's index of each pair.
//! @group(0) @binding(1) var<storage, read_write> previous_index: array<u32>;
//! ```
//!
//! ```ignore
//! /// The kernel: one thread per pair.
//! pub static MATCH_PAIRS: KernelSpec = KernelSpec::new(file("match_pairs.wgsl"));
//! ```
//!
//! The spec is named after its file. Nothing on the host lists the bindings: their names and
//! kinds (uniform, storage read, storage read-write) come from naga's reflection of the
//! composed module, and [`KernelSpec::check`] fails unless they are group 0, numbered from 0.
//! The shader is where each binding is documented. A kernel is then built with [`Kernel::new`]
//! (or [`Kernel::specialized`] for extra `override` values) and bound with
//! [`Kernel::bind_named`]; a field of a [`pipelines!`] struct is in
//! [`crate::registry::KERNELS`] for the checks.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use crate::layout::WORK_LIST_GROUPS_OFFSET;
use crate::shader::{
    Binding, ShaderSource, WgslFile, immediate_size, override_names, reflect_bindings,
};
use crate::{GpuContext, GpuError, constants};

/// Declares a struct of built kernels, one `pub` [`Kernel`] field per spec (documented as
/// built from it, then by the field's own docs), and its constructor `build`, which takes
/// each kernel from a function of its spec (typically `|spec| Kernel::new(ctx, spec)`, the
/// pipeline cache).
macro_rules! pipelines {
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident {
            $(
                $(#[$field_meta:meta])*
                $field:ident: $spec:path
            ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        #[derive(Clone, Debug)]
        $vis struct $name {
            $(
                #[doc = concat!("Built from [`", stringify!($spec), "`].")]
                $(#[$field_meta])*
                pub $field: $crate::kernel::Kernel,
            )*
        }

        impl $name {
            /// The spec of every kernel, in field order.
            pub const SPECS: &'static [&'static $crate::kernel::KernelSpec] = &[$(&$spec),*];

            /// Every kernel, each from `kernel`.
            pub fn build(
                mut kernel: impl FnMut(
                    &'static $crate::kernel::KernelSpec,
                ) -> Result<$crate::kernel::Kernel, $crate::GpuError>,
            ) -> Result<Self, $crate::GpuError> {
                Ok(Self {
                    $($field: kernel(&$spec)?,)*
                })
            }
        }
    };
}
pub(crate) use pipelines;

/// A kernel: its file. Everything else (binding names and kinds, override names) is read
/// from the shader.
#[derive(Debug)]
pub struct KernelSpec {
    /// The kernel's name: its file name without `.wgsl` (used in labels and errors).
    pub name: &'static str,
    /// Its WGSL file (entry point `main`); the shared files come from its directives.
    pub file: WgslFile,
    reflection: OnceLock<Result<Reflection, String>>,
}

/// What building a pipeline needs from a checked module, computed once per kernel.
#[derive(Debug)]
struct Reflection {
    text: String,
    names: Vec<String>,
    bindings: Vec<Binding>,
    overrides: Vec<String>,
    /// Bytes of immediate data (`var<immediate>`), 0 for none.
    immediate_size: u32,
}

/// A kernel file's name: the last path segment without `.wgsl`.
const fn kernel_name(path: &'static str) -> &'static str {
    let bytes = path.as_bytes();
    let suffix = b".wgsl";
    assert!(bytes.len() > suffix.len(), "a kernel file is named *.wgsl");
    let end = bytes.len() - suffix.len();
    let mut i = 0;
    while i < suffix.len() {
        assert!(bytes[end + i] == suffix[i], "a kernel file is named *.wgsl");
        i += 1;
    }
    let mut start = 0;
    let mut i = 0;
    while i < end {
        if bytes[i] == b'/' {
            start = i + 1;
        }
        i += 1;
    }
    let (head, _) = bytes.split_at(end);
    let (_, name) = head.split_at(start);
    match std::str::from_utf8(name) {
        Ok(name) => name,
        Err(_) => panic!("kernel file names are UTF-8"),
    }
}

/// Every host value a shader may declare as an `override`: the shared, solver and sleep
/// constants, each name once.
fn host_override_values() -> Vec<(&'static str, f64)> {
    let mut values = constants::shader_constants();
    for (name, value) in crate::solver::constants::solver_constants()
        .into_iter()
        .chain(crate::sleep::constants::sleep_constants())
    {
        match values.iter().find(|(n, _)| *n == name) {
            Some(&(_, known)) => debug_assert_eq!(known, value, "{name} has two values"),
            None => values.push((name, value)),
        }
    }
    values
}

impl KernelSpec {
    /// The spec of the kernel in `file`.
    pub const fn new(file: WgslFile) -> Self {
        Self {
            name: kernel_name(file.path),
            file,
            reflection: OnceLock::new(),
        }
    }

    /// The kernel's file with every file it requires, in composition order.
    pub fn source(&self) -> Result<ShaderSource, GpuError> {
        ShaderSource::of(self.file).map_err(|e| self.error(e.to_string()))
    }

    fn error(&self, message: String) -> GpuError {
        GpuError::Shader {
            shader: self.name,
            message,
        }
    }

    /// Parses and validates the shader and checks that its buffer bindings are group 0,
    /// numbered from 0 (a bind group is built by index from [`Self::buffers`]).
    pub fn check(&self) -> Result<naga::Module, GpuError> {
        self.checked().map(|(module, _)| module)
    }

    /// [`Self::check`] with the validator's module info.
    fn checked(&self) -> Result<(naga::Module, naga::valid::ModuleInfo), GpuError> {
        let source = self.source()?;
        let module = source.parse(self.name)?;
        let info = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            crate::validation_capabilities(),
        )
        .validate(&module)
        .map_err(|e| self.error(e.emit_to_string(&source.compose())))?;
        let found = reflect_bindings(&module);
        let numbered = found
            .iter()
            .enumerate()
            .all(|(i, b)| b.group == 0 && b.binding == i as u32);
        if !numbered {
            let shader: Vec<String> = found
                .iter()
                .map(|b| format!("@group({}) @binding({}) {}", b.group, b.binding, b.name))
                .collect();
            return Err(self.error(format!(
                "the bindings {shader:?} are not group 0 numbered from 0"
            )));
        }
        Ok((module, info))
    }

    /// The checked module's bindings and override names, computed on first use.
    fn reflection(&self) -> Result<&Reflection, GpuError> {
        self.reflection
            .get_or_init(|| {
                let module = self.check().map_err(|e| match e {
                    GpuError::Shader { message, .. } => message,
                    other => other.to_string(),
                })?;
                let found = reflect_bindings(&module);
                Ok(Reflection {
                    text: self.source().map_err(|e| e.to_string())?.compose(),
                    names: found.iter().map(|b| b.name.clone()).collect(),
                    bindings: found.iter().map(|b| b.kind).collect(),
                    overrides: override_names(&module),
                    immediate_size: immediate_size(&module),
                })
            })
            .as_ref()
            .map_err(|message| self.error(message.clone()))
    }

    /// The names of its buffer bindings, in binding order: the names [`Kernel::bind_named`]
    /// asks for.
    pub fn buffers(&self) -> Result<Vec<&str>, GpuError> {
        Ok(self
            .reflection()?
            .names
            .iter()
            .map(String::as_str)
            .collect())
    }

    /// Whether the shader declares the `override` `name`.
    pub fn declares(&self, name: &str) -> Result<bool, GpuError> {
        Ok(self.reflection()?.overrides.iter().any(|o| o == name))
    }

    /// The entries of `values` this shader declares as overrides (switches that only some
    /// kernels of a stage have, such as the effect switches).
    pub fn declared(
        &self,
        values: &[(&'static str, f64)],
    ) -> Result<Vec<(&'static str, f64)>, GpuError> {
        let mut kept = Vec::new();
        for &(name, value) in values {
            if self.declares(name)? {
                kept.push((name, value));
            }
        }
        Ok(kept)
    }

    /// The override values this kernel is built with, sorted by name: the host constants
    /// its module declares, then `extra` (specializations such as effect switches) on top.
    /// Errs on an `extra` value the shader lacks.
    pub fn override_values(
        &self,
        extra: &[(&'static str, f64)],
    ) -> Result<Vec<(&'static str, f64)>, GpuError> {
        let names = &self.reflection()?.overrides;
        let mut values: Vec<(&'static str, f64)> = host_override_values()
            .into_iter()
            .filter(|(n, _)| names.iter().any(|m| m == n))
            .collect();
        for &(name, value) in extra {
            if !names.iter().any(|m| m == name) {
                return Err(self.error(format!("no override named {name} to specialize")));
            }
            values.retain(|(n, _)| *n != name);
            values.push((name, value));
        }
        values.sort_by(|a, b| a.0.cmp(b.0));
        Ok(values)
    }

    /// Like [`Self::check`], then specializes the module with the override values (plus
    /// `extra`) and validates the result again, as wgpu does when it builds the pipeline.
    pub fn check_specialized(
        &self,
        extra: &[(&'static str, f64)],
    ) -> Result<(naga::Module, naga::valid::ModuleInfo), GpuError> {
        let (module, info) = self.checked()?;
        let mut constants = naga::back::PipelineConstants::default();
        for (name, value) in self.override_values(extra)? {
            constants.insert(name.to_string(), value);
        }
        let (specialized, info) = naga::back::pipeline_constants::process_overrides(
            &module,
            &info,
            Some((naga::ShaderStage::Compute, "main")),
            &constants,
        )
        .map_err(|e| self.error(e.to_string()))?;
        Ok((specialized.into_owned(), info.into_owned()))
    }
}

/// A built kernel: compute pipeline plus the layout of its single bind group. Cheap to clone
/// (the GPU objects are shared).
#[derive(Clone, Debug)]
pub struct Kernel {
    /// What it was built from.
    pub spec: &'static KernelSpec,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    /// Its bindings' names, in binding order (the spec's reflection, which lives as long).
    names: &'static [String],
}

/// Pipelines by kernel and override values (as bits).
type PipelineKey = (&'static str, Vec<(&'static str, u64)>);

/// Every pipeline built on one device, shared after (pipeline creation is the slow part of
/// starting a world: on a software rasterizer the fused solver kernel alone takes a large
/// fraction of a second to compile). Each [`GpuContext`] holds its own, so a pipeline is never
/// handed to another device (wgpu devices of two instances can compare equal) and the
/// pipelines go with the device.
#[derive(Clone, Debug, Default)]
pub struct PipelineCache(Arc<Mutex<HashMap<PipelineKey, Kernel>>>);

impl Kernel {
    /// The pipeline with the host constants.
    pub fn new(ctx: &GpuContext, spec: &'static KernelSpec) -> Result<Self, GpuError> {
        Self::specialized(ctx, spec, &[])
    }

    /// The pipeline with extra `override` values (effects compiled in or out, a pass kind),
    /// each of which the shader must declare. Built on first use per device and values, and
    /// shared after.
    pub fn specialized(
        ctx: &GpuContext,
        spec: &'static KernelSpec,
        overrides: &[(&'static str, f64)],
    ) -> Result<Self, GpuError> {
        let constants = spec.override_values(overrides)?;
        let key: PipelineKey = (
            spec.name,
            constants.iter().map(|&(n, v)| (n, v.to_bits())).collect(),
        );
        let cache = &ctx.pipelines.0;
        if let Some(found) = cache.lock().expect("pipeline cache lock").get(&key) {
            return Ok(found.clone());
        }
        // Built outside the lock: another thread building the same pipeline only wastes time.
        let built = Self::build(ctx, spec, &constants)?;
        Ok(cache
            .lock()
            .expect("pipeline cache lock")
            .entry(key)
            .or_insert(built)
            .clone())
    }

    fn build(
        ctx: &GpuContext,
        spec: &'static KernelSpec,
        constants: &[(&'static str, f64)],
    ) -> Result<Self, GpuError> {
        let reflection = spec.reflection()?;
        let device = &ctx.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let desc = wgpu::ShaderModuleDescriptor {
            label: Some(spec.name),
            source: wgpu::ShaderSource::Wgsl(reflection.text.as_str().into()),
        };
        // SAFETY: `runtime_checks` keeps naga's bounds checks; it only leaves out the loop
        // counter naga adds to every loop, whose one job is to end a loop that would never
        // end. Every loop of the crate's WGSL ends by its own condition (see
        // `runtime_checks`), so the counter has nothing to catch.
        let shader = unsafe { device.create_shader_module_trusted(desc, runtime_checks()) };
        let entries: Vec<wgpu::BindGroupLayoutEntry> = reflection
            .bindings
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupLayoutEntry {
                binding: i as u32,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: b.layout_type(),
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
            immediate_size: reflection.immediate_size,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(spec.name),
            layout: Some(&pipeline_layout),
            module: &shader,
            entry_point: Some("main"),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants,
                zero_initialize_workgroup_memory: true,
            },
            cache: None,
        });
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(spec.error(error.to_string()));
        }
        Ok(Self {
            spec,
            pipeline,
            layout,
            names: &reflection.names,
        })
    }

    /// A bind group over the buffer `buffer` gives for each binding's name (whole buffers):
    /// a stage that names its buffers as its kernels' bindings looks every kernel's arguments
    /// up in one place instead of listing them kernel by kernel.
    pub fn bind_named<'a>(
        &self,
        ctx: &GpuContext,
        buffer: impl Fn(&'static str) -> &'a wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry> = self
            .names
            .iter()
            .enumerate()
            .map(|(i, name)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: buffer(name).as_entire_binding(),
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

    /// Sets the pipeline and `group` on `pass` for the dispatches that follow, made on the
    /// pass itself (a kernel with immediate data sets them between its dispatches).
    pub fn set(&self, pass: &mut wgpu::ComputePass<'_>, group: &wgpu::BindGroup) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
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

    /// Dispatches one thread per item of the `WorkList` `work`, with the workgroup counts the
    /// GPU wrote into it.
    pub fn dispatch_work(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        group: &wgpu::BindGroup,
        work: &wgpu::Buffer,
    ) {
        self.dispatch_indirect(pass, group, work, WORK_LIST_GROUPS_OFFSET);
    }
}

/// The checks naga compiles into every kernel: its bounds checks (an index past an array's
/// end reads zero and skips the write), without the counter `force_loop_bounding` adds to
/// each loop to break out of one that never ends. `TUMBLE_SHADER_LOOP_BOUNDING=1` puts the
/// counters back.
///
/// Every loop in `shaders/` ends by its own condition: `for` loops up to constants, to the
/// solver's iteration and substep counts, and to counts and offsets the kernels or the host
/// wrote, which never exceed a buffer's element count (far from `u32::MAX`, so no index
/// wraps); the coloring's `COLOR_ROUNDS`; strides that halve; a binary search that halves its
/// range (`match_pairs`); an insertion sort that moves left (`common/reduce.wgsl`); and the
/// sweep's tile loop, which advances one workgroup of boxes per turn and stops at the last
/// box (`sweep_pairs`). The counters cost time on every turn: on an H200 (Vulkan, driver
/// 580.159.04) they were 10 to 15% of the GPU step of the packed pyramids of 24 to 100, in
/// the collision, coloring and prepare kernels; on lavapipe 20 to 25% of the solve
/// (docs/gpu-solver.md, "Loop counters"). The results are the same bits either way: the
/// counters never fire.
pub(crate) fn runtime_checks() -> wgpu::ShaderRuntimeChecks {
    let loop_bounding = std::env::var("TUMBLE_SHADER_LOOP_BOUNDING").as_deref() == Ok("1");
    wgpu::ShaderRuntimeChecks {
        force_loop_bounding: loop_bounding,
        ..wgpu::ShaderRuntimeChecks::checked()
    }
}

#[cfg(test)]
mod tests {
    use super::{kernel_name, runtime_checks};

    #[test]
    fn a_kernel_is_named_after_its_file() {
        assert_eq!(kernel_name("match_pairs.wgsl"), "match_pairs");
        assert_eq!(kernel_name("solver/solve_color.wgsl"), "solve_color");
    }

    #[test]
    fn kernels_keep_bounds_checks_and_leave_out_loop_counters_unless_asked() {
        let checks = runtime_checks();
        // Bounds checks are what keeps a bad index inside its buffer: never off.
        assert!(checks.bounds_checks);
        let asked = std::env::var("TUMBLE_SHADER_LOOP_BOUNDING").as_deref() == Ok("1");
        assert_eq!(checks.force_loop_bounding, asked);
    }
}
