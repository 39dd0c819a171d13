//! `collide_cuboids`: the box-box narrow phase, one manifold per candidate pair. Its CPU
//! twin is `tumble_narrow::collide_cuboids_cached` with `tumble_narrow::pair_margin` (inputs
//! converted by [`super::cuboid_from_gpu`] and [`super::box_motion`]).

use tumble_geometry::FeatureKind;

use crate::constants::{MANIFOLD_EDGE, MANIFOLD_FACE_A, MANIFOLD_FACE_B};
use crate::kernel::KernelSpec;
use crate::shader::file;

/// The kernel: one thread per pair.
pub static COLLIDE_CUBOIDS: KernelSpec = KernelSpec::new(file("collide_cuboids.wgsl"));

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
