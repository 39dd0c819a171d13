//! Which candidate pairs the caller wants.

use tumble_geometry::Aabb;

use crate::BroadPhaseError;

/// Errs unless there is one static flag per box.
pub(crate) fn check_flags(aabbs: &[Aabb], is_static: &[bool]) -> Result<(), BroadPhaseError> {
    if aabbs.len() == is_static.len() {
        Ok(())
    } else {
        Err(BroadPhaseError::FlagCountMismatch {
            boxes: aabbs.len(),
            flags: is_static.len(),
        })
    }
}

/// A pair is wanted unless both boxes are static: two bodies that cannot move need no
/// contact, however much they overlap (floors meeting walls, for instance).
#[inline]
pub(crate) fn wanted(is_static: &[bool], i: u32, j: u32) -> bool {
    !(is_static[i as usize] && is_static[j as usize])
}
