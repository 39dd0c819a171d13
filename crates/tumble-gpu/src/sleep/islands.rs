//! The island search on the GPU: connected components of the step's manifolds between
//! linkable bodies (awake and dynamic), by label propagation. Every body starts as its own
//! label; a round hooks, for each link whose two labels differ, the larger label onto the
//! smaller (`hook_labels`, atomicMin into a copy of the labels), then replaces each label by
//! the label it points at (`jump_labels`). After [`super::constants::ISLAND_ROUNDS`] rounds,
//! `check_labels` flags a search in which some link still joins two labels.
//!
//! Each round reads one buffer and writes another, and atomicMin is commutative, so a round's
//! result does not depend on thread order: the GPU's labels equal `tumble_solver::island_search`'s
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
