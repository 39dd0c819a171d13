//! `match_pairs`: each pair's index in last step's sorted pair list, by binary search.

use crate::constants::NO_PREVIOUS;
use crate::kernel::KernelSpec;
use crate::shader::file;

/// The kernel: one thread per pair.
pub static MATCH_PAIRS: KernelSpec = KernelSpec::new(file("match_pairs.wgsl"));

/// The CPU twin of [`MATCH_PAIRS`]: `previous` must be sorted, as the GPU's lists are.
pub fn match_pairs_cpu(pairs: &[(u32, u32)], previous: &[(u32, u32)]) -> Vec<u32> {
    pairs
        .iter()
        .map(|p| previous.binary_search(p).map_or(NO_PREVIOUS, |i| i as u32))
        .collect()
}
