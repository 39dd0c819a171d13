//! `match_pairs`: each pair's index in last step's sorted pair list, by binary search.

use crate::constants::NO_PREVIOUS;
use crate::kernel::{KernelArgs, KernelSpec};
use crate::shader::{Binding, ShaderSource, common, wgsl_file};

/// The kernel: one thread per pair.
pub static MATCH_PAIRS: KernelSpec = KernelSpec {
    name: "match_pairs",
    source: ShaderSource {
        common: &[common::CONSTANTS, common::INDEXING, common::LAYOUT],
        kernel: wgsl_file!("match_pairs.wgsl"),
    },
    bindings: &[
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`MATCH_PAIRS`].
pub struct MatchPairsArgs<'a> {
    /// This step's pair `WorkList`.
    pub work: &'a wgpu::Buffer,
    /// This step's sorted pairs, first bodies.
    pub pair_a: &'a wgpu::Buffer,
    /// This step's sorted pairs, second bodies.
    pub pair_b: &'a wgpu::Buffer,
    /// Last step's pair `WorkList`.
    pub previous_work: &'a wgpu::Buffer,
    /// Last step's sorted pairs, first bodies.
    pub previous_a: &'a wgpu::Buffer,
    /// Last step's sorted pairs, second bodies.
    pub previous_b: &'a wgpu::Buffer,
    /// Output: last step's index of each pair, or `NO_PREVIOUS`.
    pub previous_index: &'a wgpu::Buffer,
}

impl KernelArgs for MatchPairsArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.work,
            self.pair_a,
            self.pair_b,
            self.previous_work,
            self.previous_a,
            self.previous_b,
            self.previous_index,
        ]
    }
}

/// The CPU twin of [`MATCH_PAIRS`]: `previous` must be sorted, as the GPU's lists are.
pub fn match_pairs_cpu(pairs: &[(u32, u32)], previous: &[(u32, u32)]) -> Vec<u32> {
    pairs
        .iter()
        .map(|p| previous.binary_search(p).map_or(NO_PREVIOUS, |i| i as u32))
        .collect()
}
