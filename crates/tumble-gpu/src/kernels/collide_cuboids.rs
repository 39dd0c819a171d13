//! `collide_cuboids`: the box-box narrow phase, one manifold per candidate pair. Its CPU
//! twin is `tumble_narrow::collide_cuboids_cached` with `tumble_narrow::pair_margin` (inputs
//! converted by [`super::cuboid_from_gpu`] and [`super::box_motion`]).

use tumble_geometry::FeatureKind;

use crate::constants::{MANIFOLD_EDGE, MANIFOLD_FACE_A, MANIFOLD_FACE_B};
use crate::kernel::{Kernel, KernelSpec};
use crate::shader::file;
use crate::{GpuContext, GpuError};

/// The kernel: one thread per pair.
pub static COLLIDE_CUBOIDS: KernelSpec = KernelSpec::new(file("collide_cuboids.wgsl"));

/// Whether [`COLLIDE_CUBOIDS`] on `device_type` lists the pairs of a workgroup that need the
/// full test before running them on its first threads (its `COMPACT_FRESH_PAIRS`): on GPUs,
/// where a warp runs as long as its slowest thread. Measured on an H100 (Vulkan, driver
/// 580.159.04, `step_table --backends gpu`, 4 substeps), the narrow phase went from 1.07 to
/// 0.63 ms on the pyramid of 50 (88% of its manifolds recycled) and from 9.51 to 5.23 ms on
/// the pyramid of 100 (80%), with the same pose hashes. Not on CPU adapters: on lavapipe the
/// two workgroup barriers it needs took the narrow phase of 256 columns of 20 (every manifold
/// recycled) from 7.8-8.2 to 10.1-10.6 ms.
pub fn compact_fresh_pairs(device_type: wgpu::DeviceType) -> bool {
    device_type != wgpu::DeviceType::Cpu
}

/// The [`COLLIDE_CUBOIDS`] pipeline for `ctx`'s device: listing fresh pairs first when
/// `compact` says so, or where [`compact_fresh_pairs`] does when it is `None`.
pub fn collide_cuboids_kernel(ctx: &GpuContext, compact: Option<bool>) -> Result<Kernel, GpuError> {
    let compact = compact.unwrap_or_else(|| compact_fresh_pairs(ctx.info.device_type));
    Kernel::specialized(
        ctx,
        &COLLIDE_CUBOIDS,
        &[("COMPACT_FRESH_PAIRS", f64::from(u8::from(compact)))],
    )
}

/// `GpuManifold::kind` of a CPU feature kind.
pub fn kind_code(kind: FeatureKind) -> u32 {
    match kind {
        FeatureKind::FaceA => MANIFOLD_FACE_A,
        FeatureKind::FaceB => MANIFOLD_FACE_B,
        FeatureKind::Edge => MANIFOLD_EDGE,
    }
}

/// The CPU feature kind of a `GpuManifold::kind` code.
pub fn kind_from_code(code: u32) -> FeatureKind {
    match code {
        MANIFOLD_FACE_A => FeatureKind::FaceA,
        MANIFOLD_FACE_B => FeatureKind::FaceB,
        _ => FeatureKind::Edge,
    }
}
