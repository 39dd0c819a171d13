//! Tumble's broad phase: each box's AABB for the step ([`update_aabbs`]), the pairs of
//! overlapping AABBs, and the brute-force reference every method must equal.
//!
//! - [`BroadPhase`] (and [`broad_phase_pairs`]): the step's, a uniform grid of cells one
//!   typical box across, with a side list for the few much larger boxes (module `grid`).
//! - [`SweepAndPrune`] (and [`sweep_and_prune`]): a one-axis sweep along the axis of largest
//!   spread, the algorithm of the GPU backend, kept as its CPU twin and a second reference.
//! - [`brute_force_pairs`]: every pair tested.
//!
//! Contract shared by every function here (and by the GPU kernels that mirror them): the
//! result lists each overlapping pair once as `(i, j)` with `i < j` (indices into the input
//! slice), sorted ascending; overlap uses closed intervals, as `Aabb::intersects`, so boxes
//! that exactly touch form a pair (a resting box's AABB touches the floor's).
//!
//! ```
//! use tumble_broad::{broad_phase_pairs, brute_force_pairs, sweep_and_prune};
//! use tumble_geometry::{Aabb, Point3};
//!
//! let aabbs = [
//!     Aabb::new(Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 1.0, 1.0)),
//!     // Touches box 0 at x = 1: closed intervals make this a pair.
//!     Aabb::new(Point3::new(1.0, 0.0, 0.0), Point3::new(2.0, 1.0, 1.0)),
//!     // Far from both.
//!     Aabb::new(Point3::new(5.0, 5.0, 5.0), Point3::new(6.0, 6.0, 6.0)),
//! ];
//! let pairs = broad_phase_pairs(&aabbs);
//! assert_eq!(pairs, vec![(0, 1)]);
//! assert_eq!(pairs, brute_force_pairs(&aabbs), "the grid equals the reference");
//! assert_eq!(pairs, sweep_and_prune(&aabbs), "and so does the sweep");
//! ```
#![warn(missing_docs)]

mod brute_force;
mod cell_size;
mod error;
mod filter;
mod grid;
mod grid_query;
#[cfg(test)]
mod grid_tests;
mod kept;
mod motion;
mod sweep_and_prune;
mod sweep_axis;
#[cfg(test)]
mod tests;

pub use brute_force::{brute_force_pairs, brute_force_pairs_filtered};
pub use error::BroadPhaseError;
pub use filter::{CollisionGroups, wanted as is_wanted_pair};
pub use grid::{
    BroadPhase, broad_phase_pairs, broad_phase_pairs_filtered, broad_phase_pairs_grouped,
};
pub use kept::{FAT_FRACTION, KeptPairs, REPAIR_MAX, RETRY_EVERY};
pub use motion::{motion_aabb, update_aabbs};
pub use sweep_and_prune::{SweepAndPrune, sweep_and_prune, sweep_and_prune_filtered};
pub use sweep_axis::sweep_axis;

/// The pair list of a one-shot query: `query` run on a fresh list (the body the free functions
/// `broad_phase_pairs_*` and `sweep_and_prune_*` share).
fn collect_pairs<E>(
    query: impl FnOnce(&mut Vec<(u32, u32)>) -> Result<(), E>,
) -> Result<Vec<(u32, u32)>, E> {
    let mut out = Vec::new();
    query(&mut out)?;
    Ok(out)
}

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
