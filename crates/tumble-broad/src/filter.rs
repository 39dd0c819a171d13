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

/// A pair is wanted unless both boxes are static. "Static" means contacts cannot move the
/// body (fixed and kinematic bodies): two such bodies need no contact, however much they
/// overlap (a floor meeting a wall, a kinematic platform passing through the floor).
#[inline]
pub(crate) fn wanted(is_static: &[bool], i: u32, j: u32) -> bool {
    !(is_static[i as usize] && is_static[j as usize])
}
