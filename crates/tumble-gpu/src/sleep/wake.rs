//! Waking: `wake_bodies` flags the islands of the bodies the host touched, `wake_islands`
//! wakes every body of a flagged island at the start of a step and counts the bodies the
//! step moves. Their CPU twins are
//! [`tumble_solver::SleepLabels::wake_bodies`] and [`tumble_solver::SleepLabels::wake_islands`].

use crate::kernel::KernelSpec;
use crate::shader::file;

/// Kernel: a single thread, queued bodies in order.
pub static WAKE_BODIES: KernelSpec = KernelSpec::new(file("sleep/wake_bodies.wgsl"));

/// Kernel: one thread per body.
pub static WAKE_ISLANDS: KernelSpec = KernelSpec::new(file("sleep/wake_islands.wgsl"));
