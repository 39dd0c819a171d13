//! The island search on the GPU: connected components of the step's manifolds between
//! linkable bodies (awake and dynamic), by label propagation. Every body starts as its own
//! label; a round hooks, for each link whose two labels differ, the larger label onto the
//! smaller (`hook_labels`, atomicMin into a copy of the labels), then replaces each label by
//! the label it points at (`jump_labels`). After [`super::constants::ISLAND_ROUNDS`] rounds,
//! `check_labels` flags a search in which some link still joins two labels.
//!
//! Each round reads one buffer and writes another, and atomicMin is commutative, so a round's
//! result does not depend on thread order: the GPU's labels equal [`island_search_cpu`]'s
//! bit for bit. A finished search labels each island with its smallest body index, the
//! labels `tumble_solver::Islands` gives.

use crate::kernel::{KernelArgs, KernelSpec};
use crate::shader::{Binding, ShaderSource, wgsl_file};

use super::shaders::SLEEP_COMMON;

/// Kernel: one thread per manifold (dispatched indirectly from the pair work list).
pub static HOOK_LABELS: KernelSpec = KernelSpec {
    name: "hook_labels",
    source: ShaderSource {
        common: SLEEP_COMMON,
        kernel: wgsl_file!("sleep/hook_labels.wgsl"),
    },
    bindings: &[
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`HOOK_LABELS`] and [`CHECK_LABELS`] (whose last buffer is the one-entry
/// `unfinished` flag instead of `next_labels`).
pub struct LinkLabelsArgs<'a> {
    /// The step's pair `WorkList`.
    pub work: &'a wgpu::Buffer,
    /// `array<GpuManifold>`: the step's manifolds.
    pub manifolds: &'a wgpu::Buffer,
    /// `array<GpuBody>`: every body as uploaded.
    pub awake_bodies: &'a wgpu::Buffer,
    /// `array<u32>`: island labels (which bodies sleep).
    pub island: &'a wgpu::Buffer,
    /// `array<u32>`: the round's labels.
    pub labels: &'a wgpu::Buffer,
    /// `array<atomic<u32>>`: what the kernel lowers or flags.
    pub output: &'a wgpu::Buffer,
}

impl KernelArgs for LinkLabelsArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.work,
            self.manifolds,
            self.awake_bodies,
            self.island,
            self.labels,
            self.output,
        ]
    }
}

/// Kernel: one thread per body.
pub static JUMP_LABELS: KernelSpec = KernelSpec {
    name: "jump_labels",
    source: ShaderSource {
        common: SLEEP_COMMON,
        kernel: wgsl_file!("sleep/jump_labels.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`JUMP_LABELS`].
pub struct JumpLabelsArgs<'a> {
    /// `SleepParams`.
    pub params: &'a wgpu::Buffer,
    /// `array<u32>`: the labels after this round's hooks.
    pub next_labels: &'a wgpu::Buffer,
    /// `array<u32>`: the round's result.
    pub labels: &'a wgpu::Buffer,
    /// `array<u32>`: the same result, the copy the next round hooks into.
    pub spare: &'a wgpu::Buffer,
}

impl KernelArgs for JumpLabelsArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![self.params, self.next_labels, self.labels, self.spare]
    }
}

/// Kernel: one thread per manifold (dispatched indirectly from the pair work list).
pub static CHECK_LABELS: KernelSpec = KernelSpec {
    name: "check_labels",
    source: ShaderSource {
        common: SLEEP_COMMON,
        kernel: wgsl_file!("sleep/check_labels.wgsl"),
    },
    bindings: &[
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// The result of an island search.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct IslandSearch {
    /// Each body's label after the last round (a body index of its island).
    pub labels: Vec<u32>,
    /// True when no link joins two labels: each island is labelled with its smallest body.
    pub finished: bool,
}

/// The CPU twin of the search: `rounds` rounds of `hook_labels` and `jump_labels` over
/// `links` (pairs of body indices; a link counts when both its bodies are `linkable`), then
/// `check_labels`. Bit-for-bit the labels the kernels compute.
pub fn island_search_cpu(linkable: &[bool], links: &[(u32, u32)], rounds: u32) -> IslandSearch {
    let n = linkable.len();
    let counts = |&(a, b): &(u32, u32)| linkable[a as usize] && linkable[b as usize];
    let mut labels: Vec<u32> = (0..n as u32).collect();
    for _ in 0..rounds {
        let mut next = labels.clone();
        for &(a, b) in links.iter().filter(|l| counts(l)) {
            let (la, lb) = (labels[a as usize], labels[b as usize]);
            if la != lb {
                let slot = &mut next[la.max(lb) as usize];
                *slot = (*slot).min(la.min(lb));
            }
        }
        labels = (0..n).map(|i| next[next[i] as usize]).collect();
    }
    let finished = links
        .iter()
        .filter(|l| counts(l))
        .all(|&(a, b)| labels[a as usize] == labels[b as usize]);
    IslandSearch { labels, finished }
}
