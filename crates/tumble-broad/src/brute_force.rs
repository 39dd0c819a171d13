//! The reference broad phase: every pair tested.

use tumble_geometry::Aabb;

use crate::BroadPhaseError;
use crate::filter::{check_flags, wanted};

/// Every overlapping pair `(i, j)`, `i < j`, sorted ascending, by testing all `n (n - 1) / 2`
/// pairs with `Aabb::intersects` (closed intervals: exactly touching boxes form a pair).
///
/// O(n^2): the reference that `BroadPhase` and `sweep_and_prune` must equal exactly.
pub fn brute_force_pairs(aabbs: &[Aabb]) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for (i, a) in aabbs.iter().enumerate() {
        for (j, b) in aabbs.iter().enumerate().skip(i + 1) {
            if a.intersects(b) {
                out.push((i as u32, j as u32));
            }
        }
    }
    // Generated in lexicographic order already: no sort needed.
    out
}

/// As `brute_force_pairs`, leaving out pairs of two boxes flagged static.
pub fn brute_force_pairs_filtered(
    aabbs: &[Aabb],
    is_static: &[bool],
) -> Result<Vec<(u32, u32)>, BroadPhaseError> {
    check_flags(aabbs, is_static)?;
    Ok(brute_force_pairs(aabbs)
        .into_iter()
        .filter(|&(i, j)| wanted(is_static, i, j))
        .collect())
}
