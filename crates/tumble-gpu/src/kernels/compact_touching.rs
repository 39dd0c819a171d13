//! The compaction of the manifolds in contact into a dense list in pair order
//! (`count_touching` -> `scan_touching` -> `write_touching`), and `scatter_impulses`, which
//! writes impulses given in that dense order back to the pair slots.
//!
//! Deterministic by construction: every manifold's dense position is a prefix sum, not the
//! order in which threads happened to append.

use crate::MAX_MANIFOLD_POINTS;
use crate::kernel::KernelSpec;
use crate::layout::{GpuContact, GpuManifold, GpuTouching};
use crate::shader::file;

/// Kernel: per-tile totals of manifolds in contact and of their points.
pub static COUNT_TOUCHING: KernelSpec = KernelSpec::new(file("count_touching.wgsl"));

/// Kernel: exclusive scan of the tile totals (single workgroup) and the grand totals.
pub static SCAN_TOUCHING: KernelSpec = KernelSpec::new(file("scan_touching.wgsl"));

/// Kernel: the dense writes.
pub static WRITE_TOUCHING: KernelSpec = KernelSpec::new(file("write_touching.wgsl"));

/// Kernel: dense impulses back to the pair slots.
pub static SCATTER_IMPULSES: KernelSpec = KernelSpec::new(file("scatter_impulses.wgsl"));

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
