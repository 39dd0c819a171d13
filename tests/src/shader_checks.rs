//! Checks of WGSL modules shared by the shader tests (`gpu_layout.rs`,
//! `gpu_solver_shaders.rs`, `gpu_wide_effects.rs`).

use tumble_gpu::kernel::KernelSpec;
use tumble_gpu::layout::StructLayout;
use tumble_gpu::naga;

/// `spec` specialized with `values`, as wgpu builds its pipeline; panics when it does not
/// validate, or when an override is left without a value (none may be left to the driver).
pub fn fully_specialized(
    spec: &KernelSpec,
    values: &[(&'static str, f64)],
) -> (naga::Module, naga::valid::ModuleInfo) {
    let (module, info) = spec
        .check_specialized(values)
        .unwrap_or_else(|e| panic!("{e}"));
    for (_, o) in module.overrides.iter() {
        assert!(
            o.init.is_some(),
            "{}: override {:?} has no value",
            spec.name,
            o.name
        );
    }
    (module, info)
}

/// `module`'s entry point `main` as compute SPIR-V; panics, naming kernel `name`, when naga
/// cannot write it.
pub fn compute_spirv(
    module: &naga::Module,
    info: &naga::valid::ModuleInfo,
    name: &str,
) -> Vec<u32> {
    naga::back::spv::write_vec(
        module,
        info,
        &naga::back::spv::Options::default(),
        Some(&naga::back::spv::PipelineOptions {
            shader_stage: naga::ShaderStage::Compute,
            entry_point: "main".into(),
        }),
    )
    .unwrap_or_else(|e| panic!("{name}: SPIR-V: {e}"))
}

/// Asserts that WGSL struct `name`, of `members` and `span` and laid out by naga's layouter
/// in `layout_size` bytes, has the size, field names and field offsets of its Rust twin.
pub fn assert_same_layout(
    name: &str,
    rust: &StructLayout,
    members: &[naga::StructMember],
    span: u32,
    layout_size: u32,
) {
    assert_eq!(rust.size, span as usize, "{name}: size");
    assert_eq!(rust.size, layout_size as usize, "{name}: layouter size");
    let wgsl_fields: Vec<(String, usize)> = members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize))
        .collect();
    let rust_fields: Vec<(String, usize)> = rust
        .fields
        .iter()
        .map(|&(n, o)| (n.to_string(), o))
        .collect();
    assert_eq!(rust_fields, wgsl_fields, "{name}: field names and offsets");
}

/// True when `member` of a struct of `module` is a vec3 (16-byte aligned but 12 bytes long:
/// host structs cannot mirror it without hidden padding).
pub fn is_vec3(module: &naga::Module, member: &naga::StructMember) -> bool {
    matches!(
        module.types[member.ty].inner,
        naga::TypeInner::Vector {
            size: naga::VectorSize::Tri,
            ..
        }
    )
}
