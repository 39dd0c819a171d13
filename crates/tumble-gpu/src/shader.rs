//! WGSL sources, embedded at compile time from the repository's `shaders/` folder (the
//! `tumble-shaders` crate), and how a kernel's source is composed.
//!
//! Every `.wgsl` file under `shaders/` is embedded by `tumble-shaders`' build script into one
//! table, [`FILES`], keyed by its path relative to `shaders/`. A file names the files it needs
//! in a directive among its leading comment lines:
//!
//! ```wgsl
//! // requires: common/indexing.wgsl common/layout.wgsl
//! ```
//!
//! The include mechanism is whole-file concatenation: [`ShaderSource::of`] follows these
//! directives transitively, depth first in the order written, and lists each file once, after
//! everything it requires and before the file that required it (so the order is fixed by the
//! files alone; [`tumble_shaders::compose_order`]). [`ShaderSource::compose`] then writes them
//! in that order. WGSL lets module-scope declarations appear in any order, so no file needs
//! guards or forward declarations. Nothing inside any file is ever rewritten: values such as
//! the workgroup size reach the shaders as `override` constants, and the few that WGSL needs as
//! const-expressions (array sizes, tables) as `const` declarations generated from the Rust
//! values ([`crate::constants::wgsl_const_prelude`]), composed first.
//!
//! A shader file therefore only ever names what it uses itself; a kernel
//! ([`crate::kernel::KernelSpec`]) names only its own file.

use crate::GpuError;

pub use tumble_shaders::{FILES, REQUIRES_DIRECTIVE, WgslFile, file, find};

/// A full source: a file and everything it requires, dependency first, the file itself last.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ShaderSource {
    /// The files in composition order.
    pub files: Vec<WgslFile>,
}

impl ShaderSource {
    /// `root` with the files its `// requires:` directives name, transitively, each once.
    /// Errs on a path with no embedded file or on a cycle, naming the chain.
    pub fn of(root: WgslFile) -> Result<Self, GpuError> {
        let files = tumble_shaders::compose_order(root).map_err(|message| GpuError::Shader {
            shader: root.path,
            message,
        })?;
        Ok(Self { files })
    }

    /// The file at `path` with what it requires (see [`Self::of`]).
    pub fn of_path(path: &'static str) -> Result<Self, GpuError> {
        let root = find(path).ok_or_else(|| GpuError::Shader {
            shader: path,
            message: format!("no WGSL file {path} under shaders/"),
        })?;
        Self::of(root)
    }

    /// The composed WGSL text handed to naga and wgpu.
    pub fn compose(&self) -> String {
        let mut text = crate::constants::wgsl_const_prelude();
        for file in &self.files {
            text.push_str("// ---- shaders/");
            text.push_str(file.path);
            text.push_str(" ----\n");
            text.push_str(file.source);
            text.push('\n');
        }
        text
    }

    /// Parses the composed source with naga's WGSL front end.
    pub fn parse(&self, name: &'static str) -> Result<naga::Module, GpuError> {
        let text = self.compose();
        naga::front::wgsl::parse_str(&text).map_err(|e| GpuError::Shader {
            shader: name,
            message: e.emit_to_string(&text),
        })
    }
}

/// How a kernel binds one buffer (all in bind group 0, binding = position in the list).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Binding {
    /// `var<uniform>`: small per-dispatch parameters.
    Uniform,
    /// `var<storage, read>`.
    StorageRead,
    /// `var<storage, read_write>`.
    StorageReadWrite,
}

impl Binding {
    /// The bind group layout entry type of this binding.
    pub fn layout_type(self) -> wgpu::BindingType {
        let ty = match self {
            Binding::Uniform => wgpu::BufferBindingType::Uniform,
            Binding::StorageRead => wgpu::BufferBindingType::Storage { read_only: true },
            Binding::StorageReadWrite => wgpu::BufferBindingType::Storage { read_only: false },
        };
        wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        }
    }
}

/// One buffer binding a parsed module declares.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReflectedBinding {
    /// `@group`.
    pub group: u32,
    /// `@binding`.
    pub binding: u32,
    /// The global variable's name.
    pub name: String,
    /// How it is bound.
    pub kind: Binding,
}

/// The buffer bindings a parsed module declares, ordered by group then binding number.
pub fn reflect_bindings(module: &naga::Module) -> Vec<ReflectedBinding> {
    let mut found: Vec<ReflectedBinding> = module
        .global_variables
        .iter()
        .filter_map(|(_, var)| {
            let rb = var.binding.as_ref()?;
            let kind = match var.space {
                naga::AddressSpace::Uniform => Binding::Uniform,
                naga::AddressSpace::Storage { access } => {
                    if access.contains(naga::StorageAccess::STORE) {
                        Binding::StorageReadWrite
                    } else {
                        Binding::StorageRead
                    }
                }
                _ => return None,
            };
            Some(ReflectedBinding {
                group: rb.group,
                binding: rb.binding,
                name: var.name.clone().unwrap_or_default(),
                kind,
            })
        })
        .collect();
    found.sort_by_key(|b| (b.group, b.binding));
    found
}

/// Bytes of immediate data a parsed module declares (`var<immediate>`): the size its
/// pipeline layout must give, 0 for a kernel without any.
pub fn immediate_size(module: &naga::Module) -> u32 {
    module
        .global_variables
        .iter()
        .filter(|(_, var)| var.space == naga::AddressSpace::Immediate)
        .map(|(_, var)| module.types[var.ty].inner.size(module.to_ctx()))
        .sum()
}

/// Names of the `override` constants a parsed module declares.
pub fn override_names(module: &naga::Module) -> Vec<String> {
    module
        .overrides
        .iter()
        .filter_map(|(_, o)| o.name.clone())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requirements_come_first_once_in_the_order_written() {
        let source = ShaderSource::of_path("collide_cuboids.wgsl").unwrap();
        let paths: Vec<&str> = source.files.iter().map(|f| f.path).collect();
        assert_eq!(paths.last(), Some(&"collide_cuboids.wgsl"));
        for (i, file) in source.files.iter().enumerate() {
            assert_eq!(paths.iter().filter(|p| **p == file.path).count(), 1);
            for needed in file.requires() {
                let at = paths.iter().position(|p| *p == needed).unwrap();
                assert!(at < i, "{needed} after {}", file.path);
            }
        }
    }

    #[test]
    fn every_requirement_names_an_embedded_file() {
        for file in FILES {
            ShaderSource::of(*file).unwrap_or_else(|e| panic!("{e}"));
        }
        assert!(find("common/layout.wgsl").is_some());
        assert!(find("common/no_such_file.wgsl").is_none());
    }
}
