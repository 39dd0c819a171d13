//! Rest times and falling asleep: `update_rest` (rest timers, and each body its own island),
//! `island_rest` (each island's shortest rest time), `fall_asleep` (islands that rested long
//! enough leave the step). Their CPU twins are the methods of [`tumble_solver::SleepLabels`] of the
//! same names.

use crate::kernel::KernelSpec;
use crate::shader::file;

/// Kernel: one thread per body.
pub static UPDATE_REST: KernelSpec = KernelSpec::new(file("sleep/update_rest.wgsl"));

/// Kernel: one thread per body.
pub static ISLAND_REST: KernelSpec = KernelSpec::new(file("sleep/island_rest.wgsl"));

/// Kernel: one thread per body.
pub static FALL_ASLEEP: KernelSpec = KernelSpec::new(file("sleep/fall_asleep.wgsl"));
