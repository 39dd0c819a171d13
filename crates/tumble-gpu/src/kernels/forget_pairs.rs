//! `forget_pairs`: drops the pairs of chosen worlds from last step's pair list, so the next
//! step carries nothing over for them (see the shader for why the list stays sorted).

use crate::kernel::KernelSpec;
use crate::shader::file;

/// The kernel: one thread per pair of last step's list.
pub static FORGET_PAIRS: KernelSpec = KernelSpec::new(file("forget_pairs.wgsl"));

/// The CPU twin of [`FORGET_PAIRS`]: `forget[w]` is 0 to keep world `w`'s pairs, else its
/// first body plus one; `world_of` gives a body's world.
pub fn forget_pairs_cpu(
    previous: &mut [(u32, u32)],
    world_of: impl Fn(u32) -> u32,
    forget: &[u32],
) {
    for pair in previous {
        let first = forget[world_of(pair.0) as usize];
        if first != 0 {
            *pair = (first - 1, first - 1);
        }
    }
}
