//! `check_motion`: after a step, flags the first body whose pose or velocity is not finite or
//! whose centre lies beyond `tumble_solver::bounds::MAX_POSITION` (its CPU counterpart, the
//! exact check the host then makes of the flagged state, is
//! `tumble_solver::bounds::check_motion`). Recorded by a [`crate::step::GpuWorld`] with the
//! motion check on ([`crate::step::GpuWorld::set_motion_check`]).

use crate::kernel::KernelSpec;
use crate::shader::file;

/// The kernel: one thread per body.
pub static CHECK_MOTION: KernelSpec = KernelSpec::new(file("check_motion.wgsl"));

/// The first flagged body in the flag's encoding (`0`: none; else `u32::MAX - index`).
pub fn flagged_body(flag: u32) -> Option<u32> {
    (flag != 0).then(|| u32::MAX - flag)
}

#[cfg(test)]
mod tests {
    use super::flagged_body;

    #[test]
    fn the_flag_names_the_smallest_index_and_zero_none() {
        assert_eq!(flagged_body(0), None);
        assert_eq!(flagged_body(u32::MAX), Some(0));
        assert_eq!(flagged_body(u32::MAX - 7), Some(7));
        // atomicMax of two flags keeps the smaller index.
        let (first, later) = (u32::MAX - 3, u32::MAX - 9);
        assert_eq!(flagged_body(std::cmp::max(later, first)), Some(3));
    }
}
