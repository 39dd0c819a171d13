//! `kinematic_wake`: moving kinematic bodies wake the sleeping islands their AABBs reach (the
//! broad phase pairs neither with the other). The CPU twin is
//! [`tumble_solver::SleepLabels::kinematic_wake`].

use crate::kernel::KernelSpec;
use crate::shader::file;

/// Kernel: one thread per body, looping over the kinematic bodies.
pub static KINEMATIC_WAKE: KernelSpec = KernelSpec::new(file("sleep/kinematic_wake.wgsl"));
