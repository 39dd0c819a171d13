//! The contact cache's index: which stored slot holds a body pair, built on the thread pool.
//!
//! An open-addressing table (linear probing, at most half full) of slot numbers into the
//! cache's key array, each cell a `u32` holding `slot + 1`, 0 for empty. Inserting claims a
//! cell with a compare-and-swap, so every worker inserts its own share of the keys at once.
//! The layout of the cells then depends on which worker got where first, but what a lookup
//! returns does not: each key is in the table once, and when the same pair is stored twice
//! the later slot wins (as the hash map this replaced did), whatever the order of the
//! inserts. A cell is 4 bytes, where an entry of that map held the key and the whole cached
//! manifold (well over 100 bytes), so probing touches far less memory.

use std::hash::BuildHasher;
use std::sync::atomic::{AtomicU32, Ordering};

use rayon::prelude::*;

use crate::PairKey;
use crate::pair_hash::PairBuildHasher;

/// Keys below which the table is filled on the calling thread: an insert costs tens of
/// nanoseconds, a rayon task a few microseconds.
pub(crate) const PARALLEL_MIN_KEYS: usize = 4096;

/// Keys per rayon task when filling in parallel.
const KEYS_PER_TASK: usize = 1024;

/// The cell a key's probe starts at, in a table of `mask + 1` cells.
#[inline]
fn home(key: &PairKey, mask: usize) -> usize {
    PairBuildHasher::default().hash_one(key) as usize & mask
}

/// Slot numbers by pair key; see the module documentation.
#[derive(Debug, Default)]
pub(crate) struct PairTable {
    cells: Vec<AtomicU32>,
}

impl Clone for PairTable {
    fn clone(&self) -> Self {
        Self {
            cells: self
                .cells
                .iter()
                .map(|c| AtomicU32::new(c.load(Ordering::Relaxed)))
                .collect(),
        }
    }
}

impl PairTable {
    /// Indexes `keys` (slot `i` holds `keys[i]`), reusing the cells when their count fits.
    /// Returns the number of distinct keys.
    ///
    /// # Panics
    /// When there are `u32::MAX` keys or more (a slot is a `u32`).
    pub(crate) fn rebuild(&mut self, keys: &[PairKey]) -> usize {
        assert!(
            keys.len() < u32::MAX as usize,
            "too many pairs for the table"
        );
        let size = (2 * keys.len()).next_power_of_two().max(16);
        if self.cells.len() == size {
            for c in &mut self.cells {
                *c.get_mut() = 0;
            }
        } else {
            self.cells = (0..size).map(|_| AtomicU32::new(0)).collect();
        }
        let cells = &self.cells[..];
        let insert = |slot: usize| insert(cells, keys, slot as u32);
        if keys.len() >= PARALLEL_MIN_KEYS && rayon::current_num_threads() > 1 {
            (0..keys.len())
                .into_par_iter()
                .with_min_len(KEYS_PER_TASK)
                .filter(|&s| insert(s))
                .count()
        } else {
            (0..keys.len()).filter(|&s| insert(s)).count()
        }
    }

    /// The slot of `key` among `keys` (the array the table was built from), if stored.
    #[inline]
    pub(crate) fn get(&self, keys: &[PairKey], key: &PairKey) -> Option<usize> {
        if self.cells.is_empty() {
            return None;
        }
        let mask = self.cells.len() - 1;
        let mut i = home(key, mask);
        loop {
            let cell = self.cells[i].load(Ordering::Relaxed);
            if cell == 0 {
                return None;
            }
            let slot = cell as usize - 1;
            if keys[slot] == *key {
                return Some(slot);
            }
            i = (i + 1) & mask;
        }
    }

    /// Every slot the table holds (one per distinct key), in cell order.
    pub(crate) fn slots(&self) -> impl Iterator<Item = usize> + '_ {
        self.cells
            .iter()
            .map(|c| c.load(Ordering::Relaxed))
            .filter(|&c| c != 0)
            .map(|c| c as usize - 1)
    }
}

/// Puts `slot` (holding `keys[slot]`) into `cells`; true when its key was not there yet. A key
/// already there keeps the larger of the two slots.
///
/// Relaxed ordering is enough: a cell only ever holds a slot number, the keys it points to
/// were written before the inserts began, and the caller reads the table only after every
/// insert has returned (the end of the rayon call orders them).
fn insert(cells: &[AtomicU32], keys: &[PairKey], slot: u32) -> bool {
    let key = &keys[slot as usize];
    let mask = cells.len() - 1;
    let mut i = home(key, mask);
    loop {
        let cell = &cells[i];
        let mut seen = cell.load(Ordering::Relaxed);
        loop {
            if seen == 0 {
                match cell.compare_exchange(0, slot + 1, Ordering::Relaxed, Ordering::Relaxed) {
                    Ok(_) => return true,
                    Err(now) => seen = now,
                }
                continue;
            }
            if keys[seen as usize - 1] != *key {
                break;
            }
            // The same pair stored twice: the later slot wins.
            if seen > slot {
                return false;
            }
            match cell.compare_exchange(seen, slot + 1, Ordering::Relaxed, Ordering::Relaxed) {
                Ok(_) => return false,
                Err(now) => seen = now,
            }
        }
        i = (i + 1) & mask;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pairs of a pile: body handles with a generation in the high half, each body meeting a
    /// few neighbours; `dup` of them stored a second time further on.
    fn keys(n: u64, dup: usize) -> Vec<PairKey> {
        let mut keys: Vec<PairKey> = (0..n)
            .flat_map(|i| [1, 2, 33].map(|d| (i | 1 << 32, (i + d) | 1 << 32)))
            .collect();
        let again: Vec<PairKey> = keys.iter().step_by(7).take(dup).copied().collect();
        keys.extend(again);
        keys
    }

    #[test]
    fn every_key_is_found_at_its_last_slot_on_one_thread_and_on_the_pool() {
        // 3 * 3,000 keys is past PARALLEL_MIN_KEYS, so the pool's build runs in parallel on
        // a pool of 4; the one-thread pool takes the serial path. Both must answer every
        // lookup alike: the slot of the key's last occurrence.
        let keys = keys(3000, 500);
        let distinct = 9000;
        let expect = |k: &PairKey| keys.iter().rposition(|x| x == k);
        for threads in [1, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut table = PairTable::default();
            // Twice: the second build reuses (and must clear) the first's cells.
            for _ in 0..2 {
                let n = pool.install(|| table.rebuild(&keys));
                assert_eq!(n, distinct, "{threads} threads");
                for k in &keys {
                    assert_eq!(table.get(&keys, k), expect(k), "{threads} threads");
                }
                assert_eq!(table.slots().count(), distinct);
            }
            // Pairs never stored, among them the reversed (b, a) of a stored (a, b).
            assert_eq!(table.get(&keys, &(keys[0].1, keys[0].0)), None);
            assert_eq!(table.get(&keys, &(5, 6)), None);
        }
        // An empty table finds nothing, built or not.
        let mut empty = PairTable::default();
        assert_eq!(empty.get(&[], &(1, 2)), None);
        assert_eq!(empty.rebuild(&[]), 0);
        assert_eq!(empty.get(&[], &(1, 2)), None);
    }
}
