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

use crate::kernel::KernelSpec;
use crate::shader::file;

/// Kernel: one thread per manifold (dispatched indirectly from the pair work list).
pub static HOOK_LABELS: KernelSpec = KernelSpec::new(file("sleep/hook_labels.wgsl"));

/// Kernel: one thread per manifold (dispatched indirectly from the pair work list).
pub static CHECK_LABELS: KernelSpec = KernelSpec::new(file("sleep/check_labels.wgsl"));

/// Kernel: one thread per body.
pub static JUMP_LABELS: KernelSpec = KernelSpec::new(file("sleep/jump_labels.wgsl"));
