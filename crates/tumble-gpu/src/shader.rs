//! WGSL sources, embedded at compile time from the repository's `shaders/` folder, and how a
//! kernel's source is composed.
//!
//! The include mechanism is whole-file concatenation: a kernel lists the files of
//! `shaders/common/` it needs, and [`ShaderSource::compose`] writes them, in that order, in
//! front of the kernel file. WGSL lets module-scope declarations appear in any order, so no
//! file needs guards or forward declarations. Nothing inside any file is ever rewritten:
//! values such as the workgroup size reach the shaders as `override` constants, and the few
//! that WGSL needs as const-expressions (array sizes, tables) as `const` declarations
//! generated from the Rust values ([`crate::constants::wgsl_const_prelude`]), composed first.

use crate::GpuError;

/// One WGSL file of `shaders/`, embedded in the binary.
#[derive(Clone, Copy, Debug)]
pub struct WgslFile {
    /// Path relative to `shaders/`, e.g. `common/layout.wgsl`.
    pub path: &'static str,
    /// The file's text.
    pub source: &'static str,
}

/// Embeds `shaders/<path>` as a [`WgslFile`].
macro_rules! wgsl_file {
    ($path:literal) => {
        $crate::shader::WgslFile {
            path: $path,
            source: include_str!(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../../shaders/",
                $path
            )),
        }
    };
}
pub(crate) use wgsl_file;

/// The shared files of `shaders/common/`.
pub mod common {
    use super::WgslFile;

    /// `override` declarations of the constants in [`crate::constants`].
    pub const CONSTANTS: WgslFile = wgsl_file!("common/constants.wgsl");
    /// Linear thread index over 2D-folded dispatches.
    pub const INDEXING: WgslFile = wgsl_file!("common/indexing.wgsl");
    /// The structs shared with the host (checked against Rust by the layout test).
    pub const LAYOUT: WgslFile = wgsl_file!("common/layout.wgsl");
    /// Quaternion and pose helpers.
    pub const QUAT: WgslFile = wgsl_file!("common/quat.wgsl");
    /// The narrow phase's tolerances and id layout (overrides from `tumble-narrow`).
    pub const NARROW_CONSTANTS: WgslFile = wgsl_file!("common/narrow_constants.wgsl");
    /// Two boxes in the first one's frame, box vertices, edges and faces.
    pub const BOX_PAIR: WgslFile = wgsl_file!("common/box_pair.wgsl");
    /// The separating axis test and the choice of the contact axis.
    pub const SAT: WgslFile = wgsl_file!("common/sat.wgsl");
    /// Labelled polygon clipping and the contact polygon.
    pub const CONTACT_POLYGON: WgslFile = wgsl_file!("common/contact_polygon.wgsl");
    /// Face contacts by clipping.
    pub const FACE_CONTACT: WgslFile = wgsl_file!("common/face_contact.wgsl");
    /// Edge-edge contacts and segment closest points.
    pub const EDGE_CONTACT: WgslFile = wgsl_file!("common/edge_contact.wgsl");
    /// The closest vertex pair of separated boxes.
    pub const VERTEX_CONTACT: WgslFile = wgsl_file!("common/vertex_contact.wgsl");
    /// Reduction to four points.
    pub const REDUCE: WgslFile = wgsl_file!("common/reduce.wgsl");
    /// The sweep's pair test and its long boxes.
    pub const SWEEP: WgslFile = wgsl_file!("common/sweep.wgsl");
    /// Workgroup-wide prefix sum of a tile.
    pub const TILE_SCAN: WgslFile = wgsl_file!("common/tile_scan.wgsl");
    /// The contact persistence tolerances (overrides from `tumble-solver`'s contact cache).
    pub const PERSISTENCE: WgslFile = wgsl_file!("common/persistence.wgsl");

    /// Everything the box-box narrow phase needs, in order.
    pub const NARROW_PHASE: &[WgslFile] = &[
        CONSTANTS,
        INDEXING,
        LAYOUT,
        QUAT,
        NARROW_CONSTANTS,
        BOX_PAIR,
        SAT,
        CONTACT_POLYGON,
        FACE_CONTACT,
        EDGE_CONTACT,
        VERTEX_CONTACT,
        REDUCE,
    ];

    /// Every common file, for validation and layout checks.
    pub const ALL: &[WgslFile] = &[
        CONSTANTS,
        INDEXING,
        LAYOUT,
        QUAT,
        NARROW_CONSTANTS,
        BOX_PAIR,
        SAT,
        CONTACT_POLYGON,
        FACE_CONTACT,
        EDGE_CONTACT,
        VERTEX_CONTACT,
        REDUCE,
        TILE_SCAN,
        PERSISTENCE,
        SWEEP,
    ];
}

/// A kernel's full source: common files then the kernel file.
#[derive(Clone, Copy, Debug)]
pub struct ShaderSource {
    /// Common files, concatenated in this order before the kernel.
    pub common: &'static [WgslFile],
    /// The kernel file itself (one entry point, `main`).
    pub kernel: WgslFile,
}

impl ShaderSource {
    /// The composed WGSL text handed to naga and wgpu.
    pub fn compose(&self) -> String {
        let mut text = crate::constants::wgsl_const_prelude();
        for file in self.common.iter().chain(std::iter::once(&self.kernel)) {
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

/// The buffer bindings a parsed module declares, ordered by binding number, with their group.
/// Used to check a kernel's declared [`Binding`] list against its shader.
pub fn reflect_bindings(module: &naga::Module) -> Vec<(u32, u32, Binding)> {
    let mut found: Vec<(u32, u32, Binding)> = module
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
            Some((rb.group, rb.binding, kind))
        })
        .collect();
    found.sort_by_key(|&(g, b, _)| (g, b));
    found
}

/// Names of the `override` constants a parsed module declares.
pub fn override_names(module: &naga::Module) -> Vec<String> {
    module
        .overrides
        .iter()
        .filter_map(|(_, o)| o.name.clone())
        .collect()
}
