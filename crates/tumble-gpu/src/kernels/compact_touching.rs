//! The compaction of the manifolds in contact into a dense list in pair order
//! (`count_touching` -> `scan_touching` -> `write_touching`), and `scatter_impulses`, which
//! writes impulses given in that dense order back to the pair slots.
//!
//! Deterministic by construction: every manifold's dense position is a prefix sum, not the
//! order in which threads happened to append.

use crate::MAX_MANIFOLD_POINTS;
use crate::kernel::{KernelArgs, KernelSpec};
use crate::layout::{GpuContact, GpuManifold, GpuTouching};
use crate::shader::{Binding, ShaderSource, WgslFile, common, wgsl_file};

const TILE_COMMON: &[WgslFile] = &[
    common::CONSTANTS,
    common::INDEXING,
    common::LAYOUT,
    common::TILE_SCAN,
];

/// Kernel: per-tile totals of manifolds in contact and of their points.
pub static COUNT_TOUCHING: KernelSpec = KernelSpec {
    name: "count_touching",
    source: ShaderSource {
        common: TILE_COMMON,
        kernel: wgsl_file!("count_touching.wgsl"),
    },
    bindings: &[
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// Kernel: exclusive scan of the tile totals (single workgroup) and the grand totals.
pub static SCAN_TOUCHING: KernelSpec = KernelSpec {
    name: "scan_touching",
    source: ShaderSource {
        common: TILE_COMMON,
        kernel: wgsl_file!("scan_touching.wgsl"),
    },
    bindings: &[
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Kernel: the dense writes.
pub static WRITE_TOUCHING: KernelSpec = KernelSpec {
    name: "write_touching",
    source: ShaderSource {
        common: TILE_COMMON,
        kernel: wgsl_file!("write_touching.wgsl"),
    },
    bindings: &[
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Kernel: dense impulses back to the pair slots.
pub static SCATTER_IMPULSES: KernelSpec = KernelSpec {
    name: "scatter_impulses",
    source: ShaderSource {
        common: &[common::CONSTANTS, common::INDEXING, common::LAYOUT],
        kernel: wgsl_file!("scatter_impulses.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`COUNT_TOUCHING`].
pub struct CountTouchingArgs<'a> {
    /// The pair `WorkList`.
    pub work: &'a wgpu::Buffer,
    /// Manifolds, one per pair.
    pub manifolds: &'a wgpu::Buffer,
    /// Output `array<vec2<u32>>`: (manifolds in contact, points) per tile.
    pub tile_totals: &'a wgpu::Buffer,
}

impl KernelArgs for CountTouchingArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![self.work, self.manifolds, self.tile_totals]
    }
}

/// Buffers of [`SCAN_TOUCHING`].
pub struct ScanTouchingArgs<'a> {
    /// The pair `WorkList`.
    pub work: &'a wgpu::Buffer,
    /// Tile totals in, first dense manifold and point per tile out.
    pub tile_totals: &'a wgpu::Buffer,
    /// Output `TouchingCounts`.
    pub counts: &'a wgpu::Buffer,
}

impl KernelArgs for ScanTouchingArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![self.work, self.tile_totals, self.counts]
    }
}

/// Buffers of [`WRITE_TOUCHING`].
pub struct WriteTouchingArgs<'a> {
    /// The pair `WorkList`.
    pub work: &'a wgpu::Buffer,
    /// Manifolds, one per pair.
    pub manifolds: &'a wgpu::Buffer,
    /// Points, `MAX_MANIFOLD_POINTS` per pair.
    pub contacts: &'a wgpu::Buffer,
    /// Scanned tile totals.
    pub tile_offsets: &'a wgpu::Buffer,
    /// Output `array<GpuTouching>`.
    pub touching: &'a wgpu::Buffer,
    /// Output dense manifolds.
    pub touching_manifolds: &'a wgpu::Buffer,
    /// Output dense points.
    pub touching_points: &'a wgpu::Buffer,
}

impl KernelArgs for WriteTouchingArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.work,
            self.manifolds,
            self.contacts,
            self.tile_offsets,
            self.touching,
            self.touching_manifolds,
            self.touching_points,
        ]
    }
}

/// Buffers of [`SCATTER_IMPULSES`].
pub struct ScatterImpulsesArgs<'a> {
    /// `ScatterParams` (how many dense manifolds).
    pub params: &'a wgpu::Buffer,
    /// `array<GpuTouching>` from `write_touching`.
    pub touching: &'a wgpu::Buffer,
    /// Dense manifolds from `write_touching` (for their point counts).
    pub touching_manifolds: &'a wgpu::Buffer,
    /// Impulses in dense point order (uploaded).
    pub impulses: &'a wgpu::Buffer,
    /// The per-pair points whose impulses are written.
    pub contacts: &'a wgpu::Buffer,
}

impl KernelArgs for ScatterImpulsesArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.touching,
            self.touching_manifolds,
            self.impulses,
            self.contacts,
        ]
    }
}

/// The dense contact list: where each manifold in contact sits, the manifolds, their points.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TouchingList {
    /// Pair slot and first dense point of each manifold in contact, in pair order.
    pub touching: Vec<GpuTouching>,
    /// The manifolds in contact.
    pub manifolds: Vec<GpuManifold>,
    /// Their points, manifold after manifold.
    pub points: Vec<GpuContact>,
}

/// The CPU twin of the three compaction kernels.
pub fn compact_touching_cpu(manifolds: &[GpuManifold], contacts: &[GpuContact]) -> TouchingList {
    let per = MAX_MANIFOLD_POINTS as usize;
    let mut out = TouchingList::default();
    for (k, m) in manifolds.iter().enumerate().filter(|(_, m)| m.len > 0) {
        out.touching.push(GpuTouching {
            slot: k as u32,
            first_point: out.points.len() as u32,
        });
        out.manifolds.push(*m);
        out.points
            .extend_from_slice(&contacts[k * per..k * per + m.len as usize]);
    }
    out
}

/// The CPU twin of [`SCATTER_IMPULSES`], in place on the per-pair `contacts`.
pub fn scatter_impulses_cpu(
    list: &TouchingList,
    impulses: &[GpuContact],
    contacts: &mut [GpuContact],
) {
    let per = MAX_MANIFOLD_POINTS as usize;
    for (t, m) in list.touching.iter().zip(&list.manifolds) {
        for i in 0..m.len as usize {
            let solved = &impulses[t.first_point as usize + i];
            let c = &mut contacts[t.slot as usize * per + i];
            c.normal_impulse = solved.normal_impulse;
            c.friction_impulse = solved.friction_impulse;
        }
    }
}
