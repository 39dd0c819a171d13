//! `match_pairs`: each pair's index in last step's sorted pair list, by binary search.

use crate::constants::NO_PREVIOUS;
use crate::kernel::kernel;

kernel! {
    /// Buffers of [`MATCH_PAIRS`].
    pub struct MatchPairsArgs {
        /// This step's pair `WorkList`.
        work,
        /// This step's sorted pairs, first bodies.
        pair_a,
        /// This step's sorted pairs, second bodies.
        pair_b,
        /// Last step's pair `WorkList`.
        previous_work,
        /// Last step's sorted pairs, first bodies.
        previous_a,
        /// Last step's sorted pairs, second bodies.
        previous_b,
        /// Output: last step's index of each pair, or `NO_PREVIOUS`.
        previous_index,
    }
    /// The kernel: one thread per pair.
    pub static MATCH_PAIRS = "match_pairs.wgsl";
}

/// The CPU twin of [`MATCH_PAIRS`]: `previous` must be sorted, as the GPU's lists are.
pub fn match_pairs_cpu(pairs: &[(u32, u32)], previous: &[(u32, u32)]) -> Vec<u32> {
    pairs
        .iter()
        .map(|p| previous.binary_search(p).map_or(NO_PREVIOUS, |i| i as u32))
        .collect()
}
