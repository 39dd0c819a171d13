//! `store_impulses`: each constraint's final impulses back into its contact points, where the
//! next step's matching reads them for warm starting, and its tilt impulse into the tilt
//! buffer. The CPU twin is `ContactConstraint::store_impulses` (with `ContactCache::store` for
//! the tilt's normal in body A's frame).

use crate::kernel::KernelSpec;
use crate::shader::file;

/// Kernel: one thread per constraint slot.
pub static STORE_IMPULSES: KernelSpec = KernelSpec::new(file("solver/store_impulses.wgsl"));
