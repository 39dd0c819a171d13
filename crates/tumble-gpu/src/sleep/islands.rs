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

use crate::kernel::kernel;

kernel! {
    /// Buffers of [`HOOK_LABELS`].
    pub struct HookLabelsArgs {
        /// The step's pair `WorkList`.
        work,
        /// `array<GpuManifold>`: the step's manifolds.
        manifolds,
        /// `array<GpuBody>`: every body as uploaded.
        awake_bodies,
        /// `array<u32>`: island labels (which bodies sleep).
        island,
        /// `array<u32>`: the round's labels.
        labels,
        /// `array<atomic<u32>>`: the labels the round's hooks lower.
        next_labels,
    }
    /// Kernel: one thread per manifold (dispatched indirectly from the pair work list).
    pub static HOOK_LABELS = "sleep/hook_labels.wgsl";
}

kernel! {
    /// Buffers of [`CHECK_LABELS`].
    pub struct CheckLabelsArgs {
        /// The step's pair `WorkList`.
        work,
        /// `array<GpuManifold>`: the step's manifolds.
        manifolds,
        /// `array<GpuBody>`: every body as uploaded.
        awake_bodies,
        /// `array<u32>`: island labels (which bodies sleep).
        island,
        /// `array<u32>`: the last round's labels.
        labels,
        /// One `atomic<u32>`: flagged when some link still joins two labels.
        unfinished,
    }
    /// Kernel: one thread per manifold (dispatched indirectly from the pair work list).
    pub static CHECK_LABELS = "sleep/check_labels.wgsl";
}

kernel! {
    /// Buffers of [`JUMP_LABELS`].
    pub struct JumpLabelsArgs {
        /// `SleepParams`.
        params,
        /// `array<u32>`: the labels after this round's hooks.
        next_labels,
        /// `array<u32>`: the round's result.
        labels,
        /// `array<u32>`: the same result, the copy the next round hooks into.
        spare,
    }
    /// Kernel: one thread per body.
    pub static JUMP_LABELS = "sleep/jump_labels.wgsl";
}

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
