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

/// `out` becomes the concatenation of `parts`, in order, copied on the rayon pool; `out`'s
/// allocation is kept when it is large enough (its old contents are dropped first).
pub(crate) fn concat_into<'a, T: Copy + Send + Sync + 'a>(
    parts: impl IntoIterator<Item = &'a [T]>,
    out: &mut Vec<T>,
) {
    let parts: Vec<&[T]> = parts.into_iter().collect();
    let total = parts.iter().map(|p| p.len()).sum();
    out.clear();
    out.reserve(total);
    let mut rest: &mut [MaybeUninit<T>] = &mut out.spare_capacity_mut()[..total];
    let mut targets = Vec::with_capacity(parts.len());
    for part in &parts {
        let (target, tail) = rest.split_at_mut(part.len());
        targets.push(target);
        rest = tail;
    }
    targets
        .into_par_iter()
        .zip(parts.par_iter())
        .for_each(|(target, part)| {
            for (slot, value) in target.iter_mut().zip(part.iter()) {
                slot.write(*value);
            }
        });
    // SAFETY: the targets split the first `total` spare elements into one part per piece,
    // each exactly as long as its piece, and every element of each was written above.
    unsafe { out.set_len(total) };
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
            // Into a fresh array, and into one that holds more than the result already
            // (its allocation is reused, its old contents gone).
            let mut fresh = Vec::new();
            pool.install(|| concat_into(parts.iter().map(|p| &p[..]), &mut fresh));
            assert_eq!(fresh, expected);
            let mut used: Vec<u64> = vec![7; expected.len() + 100];
            let capacity = used.capacity();
            pool.install(|| concat_into(parts.iter().map(|p| &p[..]), &mut used));
            assert_eq!(used, expected);
            assert_eq!(used.capacity(), capacity, "the larger array is reused");
        }
        let mut none = vec![1u64, 2];
        concat_into(std::iter::empty::<&[u64]>(), &mut none);
        assert!(none.is_empty());
    }
}
