//! `carry_impulses`: last step's impulses onto this step's points with the same feature id.

use crate::MAX_MANIFOLD_POINTS;
use crate::constants::NO_PREVIOUS;
use crate::kernel::{KernelArgs, KernelSpec};
use crate::layout::{GpuContact, GpuManifold};
use crate::shader::{Binding, ShaderSource, common, wgsl_file};

/// The kernel: one thread per manifold.
pub static CARRY_IMPULSES: KernelSpec = KernelSpec {
    name: "carry_impulses",
    source: ShaderSource {
        common: &[common::CONSTANTS, common::INDEXING, common::LAYOUT],
        kernel: wgsl_file!("carry_impulses.wgsl"),
    },
    bindings: &[
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`CARRY_IMPULSES`].
pub struct CarryImpulsesArgs<'a> {
    /// This step's pair `WorkList`.
    pub work: &'a wgpu::Buffer,
    /// This step's manifolds.
    pub manifolds: &'a wgpu::Buffer,
    /// Last step's manifolds.
    pub previous_manifolds: &'a wgpu::Buffer,
    /// Last step's contact points (with the solver's impulses).
    pub previous_contacts: &'a wgpu::Buffer,
    /// This step's contact points; impulses are written.
    pub contacts: &'a wgpu::Buffer,
}

impl KernelArgs for CarryImpulsesArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.work,
            self.manifolds,
            self.previous_manifolds,
            self.previous_contacts,
            self.contacts,
        ]
    }
}

/// The CPU twin of [`CARRY_IMPULSES`], in place on `contacts` (the same rule as the CPU
/// solver's contact cache: same kind and feature, then match by id).
pub fn carry_impulses_cpu(
    manifolds: &[GpuManifold],
    contacts: &mut [GpuContact],
    previous_manifolds: &[GpuManifold],
    previous_contacts: &[GpuContact],
) {
    let per = MAX_MANIFOLD_POINTS as usize;
    for (k, m) in manifolds.iter().enumerate() {
        if m.len == 0 || m.previous == NO_PREVIOUS {
            continue;
        }
        let prev = m.previous as usize;
        let old = &previous_manifolds[prev];
        if old.len == 0 || old.kind != m.kind || old.feature != m.feature {
            continue;
        }
        let before = &previous_contacts[prev * per..prev * per + old.len as usize];
        for c in &mut contacts[k * per..k * per + m.len as usize] {
            if let Some(b) = before.iter().find(|b| b.id == c.id) {
                c.normal_impulse = b.normal_impulse;
                c.friction_impulse = b.friction_impulse;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn manifold(kind: u32, feature: u32, len: u32, previous: u32) -> GpuManifold {
        GpuManifold {
            kind,
            feature,
            len,
            previous,
            ..Default::default()
        }
    }

    fn point(id: u32, impulse: f32) -> GpuContact {
        GpuContact {
            id,
            normal_impulse: impulse,
            ..Default::default()
        }
    }

    #[test]
    fn impulses_follow_ids_under_the_same_feature_only() {
        let per = MAX_MANIFOLD_POINTS as usize;
        let mut before = vec![GpuContact::default(); 2 * per];
        before[0] = point(10, 1.0);
        before[1] = point(11, 2.0);
        before[per] = point(10, 5.0);
        let old = [
            manifold(0, 2, 2, NO_PREVIOUS),
            manifold(0, 3, 1, NO_PREVIOUS),
        ];
        // Manifold 0 continues old 0 (same face 2), points reordered plus a new one; manifold
        // 1 continues old 1 but on another face: its ids mean other features, nothing carries.
        let now = [manifold(0, 2, 3, 0), manifold(0, 4, 1, 1)];
        let mut contacts = vec![GpuContact::default(); 2 * per];
        contacts[0] = point(11, 0.0);
        contacts[1] = point(99, 0.0);
        contacts[2] = point(10, 0.0);
        contacts[per] = point(10, 0.0);
        carry_impulses_cpu(&now, &mut contacts, &old, &before);
        assert_eq!(contacts[0].normal_impulse, 2.0);
        assert_eq!(contacts[1].normal_impulse, 0.0);
        assert_eq!(contacts[2].normal_impulse, 1.0);
        assert_eq!(contacts[per].normal_impulse, 0.0);
    }
}
