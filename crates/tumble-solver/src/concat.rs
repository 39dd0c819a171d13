//! Joining the pieces a parallel stage found into one array, on the pool.
//!
//! Rayon's `unzip`/`collect` of a filtered parallel iterator gathers each task's results in
//! a list of vectors, each grown by doubling, then appends them into the output on one
//! thread: the narrow phase's manifolds (some 200 bytes each, megabytes a step on a large
//! pile) were copied up to three times, the last copy serial. Here each piece is reserved
//! once at its upper bound and the pieces are copied into the output by the workers, each
//! into its own part of it.

use std::mem::MaybeUninit;

use rayon::prelude::*;

/// The concatenation of `parts`, in order, copied on the rayon pool.
pub(crate) fn concat<T: Copy + Send + Sync>(parts: &[Vec<T>]) -> Vec<T> {
    let total = parts.iter().map(Vec::len).sum();
    let mut out: Vec<T> = Vec::with_capacity(total);
    let mut rest: &mut [MaybeUninit<T>] = &mut out.spare_capacity_mut()[..total];
    let mut targets = Vec::with_capacity(parts.len());
    for part in parts {
        let (target, tail) = rest.split_at_mut(part.len());
        targets.push(target);
        rest = tail;
    }
    targets
        .into_par_iter()
        .zip(parts.par_iter())
        .for_each(|(target, part)| {
            for (slot, value) in target.iter_mut().zip(part) {
                slot.write(*value);
            }
        });
    // SAFETY: the targets split the first `total` spare elements into one part per piece,
    // each exactly as long as its piece, and every element of each was written above.
    unsafe { out.set_len(total) };
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pieces_come_out_in_order_whole() {
        let parts: Vec<Vec<u64>> = (0..37u64)
            .map(|p| (0..p * 13 % 50).map(|i| p * 1000 + i).collect())
            .collect();
        let expected: Vec<u64> = parts.iter().flatten().copied().collect();
        for threads in [1, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            assert_eq!(pool.install(|| concat(&parts)), expected);
        }
        assert_eq!(concat::<u64>(&[]), Vec::<u64>::new());
    }
}
