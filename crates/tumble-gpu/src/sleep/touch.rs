//! `touch_sleepers`: the step's manifolds wake the sleeping islands awake bodies reached, and
//! moving kinematic bodies keep what they touch from resting. The CPU twin is
//! [`tumble_solver::SleepLabels::touch_sleepers`].

use crate::kernel::KernelSpec;
use crate::shader::file;

/// Kernel: one thread per manifold (dispatched indirectly from the pair work list).
pub static TOUCH_SLEEPERS: KernelSpec = KernelSpec::new(file("sleep/touch_sleepers.wgsl"));
