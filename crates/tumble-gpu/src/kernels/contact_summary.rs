//! `contact_summary`: a step's contact counts (manifolds with points, their points, the
//! deepest overlap, the pair count, the recycled manifolds) reduced on the GPU, so that a
//! host that wants only the counts (`World::stats` on `Backend::Gpu`) reads 32 bytes instead
//! of every manifold.

use crate::MAX_MANIFOLD_POINTS;
use crate::kernel::KernelSpec;
use crate::layout::{GpuContact, GpuManifold};
use crate::shader::file;

/// Kernel: the counts of [`ContactSummary`], one thread per pair slot.
pub static CONTACT_SUMMARY: KernelSpec = KernelSpec::new(file("contact_summary.wgsl"));

/// Bytes of the kernel's output.
pub const CONTACT_SUMMARY_BYTES: u64 = 32;

/// Words of the kernel's output (the last three unused).
pub const CONTACT_SUMMARY_WORDS: usize = 8;

/// A step's contacts in five numbers.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactSummary {
    /// Manifolds with at least one point.
    pub manifolds: u32,
    /// Their points.
    pub points: u32,
    /// The deepest overlap of any point, m (0 when no point overlaps).
    pub max_depth: f32,
    /// Candidate pairs the narrow phase examined (the pair work list's count).
    pub pairs: u32,
    /// Manifolds with points reused from the step before (contact recycling).
    pub recycled: u32,
}

impl ContactSummary {
    /// The summary in the kernel's output words.
    pub fn from_words(words: [u32; CONTACT_SUMMARY_WORDS]) -> Self {
        Self {
            manifolds: words[0],
            points: words[1],
            max_depth: f32::from_bits(words[2]),
            pairs: words[3],
            recycled: words[4],
        }
    }
}

/// The CPU twin of [`CONTACT_SUMMARY`]: the summary of the first `pairs` manifolds of
/// `manifolds` and their points in `contacts` (`MAX_MANIFOLD_POINTS` per manifold).
pub fn contact_summary_cpu(
    pairs: u32,
    manifolds: &[GpuManifold],
    contacts: &[GpuContact],
) -> ContactSummary {
    let per = MAX_MANIFOLD_POINTS as usize;
    let mut out = ContactSummary {
        pairs,
        ..Default::default()
    };
    for (k, m) in manifolds.iter().enumerate().take(pairs as usize) {
        let len = m.len.min(MAX_MANIFOLD_POINTS);
        if len == 0 {
            continue;
        }
        out.manifolds += 1;
        out.recycled += u32::from(m.recycled != 0);
        out.points += len;
        for p in &contacts[k * per..k * per + len as usize] {
            if p.depth > out.max_depth {
                out.max_depth = p.depth;
            }
        }
    }
    out
}
