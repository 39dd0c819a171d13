//! `remap_pairs`: last step's pair list renumbered after the bodies were uploaded again in a
//! new order, keeping the pairs of the worlds whose bodies are unchanged and dropping the
//! others' (`GpuWorld::set_bodies_in_worlds_keeping`).
//!
//! Why the list stays sorted: it was sorted by (a, b) with each world's bodies one run and the
//! worlds in order. A kept world's bodies move by one offset and keep their order, so its pairs
//! keep theirs; a dropped world's pairs all become (f, f), with f the new index of its first
//! body (or, when it has none now, of the next world's): no kept pair of an earlier world
//! reaches f, and every pair of a later world starts at f or after. No step forms a pair of one
//! body, so (f, f) matches nothing.

use crate::kernel::KernelSpec;
use crate::shader::file;

/// The kernel: one thread per pair of last step's list.
pub static REMAP_PAIRS: KernelSpec = KernelSpec::new(file("remap_pairs.wgsl"));

/// Flag of a `remap` entry whose body's world drops its pairs; the other bits are the index
/// those pairs drop to.
pub const REMAP_DROPPED: u32 = 1 << 31;

/// The CPU twin of [`REMAP_PAIRS`].
pub fn remap_pairs_cpu(previous: &mut [(u32, u32)], remap: &[u32]) {
    for pair in previous {
        let a = remap[pair.0 as usize];
        *pair = if a & REMAP_DROPPED != 0 {
            let f = a & !REMAP_DROPPED;
            (f, f)
        } else {
            (a, remap[pair.1 as usize])
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kept_worlds_shift_and_dropped_worlds_collapse_in_order() {
        // Three worlds of 3, 2 and 3 bodies; the middle one is dropped (a body was added to
        // it: it now has 3 bodies starting at 4), the last moves up by one, a new world of one
        // body comes first (index 0), so the first world moves to 1..4.
        let mut previous = vec![(0, 1), (0, 2), (1, 2), (3, 4), (5, 6), (5, 7), (6, 7)];
        let remap = [1, 2, 3, REMAP_DROPPED | 4, REMAP_DROPPED | 4, 8, 9, 10];
        remap_pairs_cpu(&mut previous, &remap);
        assert_eq!(
            previous,
            vec![(1, 2), (1, 3), (2, 3), (4, 4), (8, 9), (8, 10), (9, 10)]
        );
        // Still sorted, as match_pairs' binary search needs.
        assert!(previous.windows(2).all(|w| w[0] <= w[1]));
    }
}
