//! `update_aabbs`: poses -> world AABBs grown by the speculative margin and swept by the
//! motion over the next step. Its CPU twin is `tumble_broad::update_aabbs` (inputs converted
//! by [`super::cuboid_from_gpu`] and [`super::velocity_from_gpu`]); the kernel adds the margin
//! and the spin before building the box and the CPU stage after, so the two round differently
//! in the last bits.

use crate::kernel::KernelSpec;
use crate::shader::file;

/// The kernel: one thread per body.
pub static UPDATE_AABBS: KernelSpec = KernelSpec::new(file("update_aabbs.wgsl"));

/// The host form of a GPU pose, for the twins' callers.
pub use crate::solver::convert::pose_from_gpu;
