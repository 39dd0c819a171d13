//! Stage 2: AABBs to candidate pairs.

use tumble_broad::SweepAndPrune;
use tumble_geometry::Aabb;
use tumble_solver::Body;

/// Overlapping AABB pairs `(i, j)`, `i < j`, sorted, leaving out pairs of two bodies that
/// contacts cannot move (fixed or kinematic on both sides: static-static is never formed).
///
/// `sap` keeps its buffers between steps.
pub fn broad_phase(sap: &mut SweepAndPrune, aabbs: &[Aabb], bodies: &[Body]) -> Vec<(u32, u32)> {
    let immovable: Vec<bool> = bodies.iter().map(|b| !b.is_dynamic()).collect();
    let mut pairs = Vec::new();
    // One flag per box by construction, so the length check cannot fail.
    sap.find_pairs_filtered(aabbs, &immovable, &mut pairs)
        .expect("one flag per body");
    pairs
}
