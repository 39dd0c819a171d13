//! A fast hasher for the contact cache's pair keys (its table of slots, `pair_table.rs`).
//!
//! The standard map's SipHash guards against keys chosen by an attacker, which pair keys (two
//! body handles) are not, and costs several times more per lookup than a multiply. This is a
//! multiply-rotate hasher of the FxHash family: each 64-bit word is folded in as
//! `(h rotl 5 ^ word) * K`, and the result is rotated so that the product's well-mixed high
//! bits also reach the low bits a hash table picks its bucket from. It has no per-process
//! seed, so it is deterministic, but nothing the step computes depends on a table's layout
//! anyway ([`crate::ContactCache::entries`] sorts).

use std::hash::{BuildHasherDefault, Hasher};

/// An odd multiplier with well-spread bits (the one FxHash uses on 64-bit targets).
const K: u64 = 0x517c_c1b7_2722_0a95;

/// The hasher; see the module documentation.
#[derive(Clone, Copy, Debug, Default)]
pub struct PairHasher {
    hash: u64,
}

impl PairHasher {
    #[inline]
    fn add(&mut self, word: u64) {
        self.hash = (self.hash.rotate_left(5) ^ word).wrapping_mul(K);
    }
}

impl Hasher for PairHasher {
    #[inline]
    fn finish(&self) -> u64 {
        self.hash.rotate_left(26)
    }

    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for chunk in &mut chunks {
            let mut word = [0u8; 8];
            word.copy_from_slice(chunk);
            self.add(u64::from_le_bytes(word));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut word = [0u8; 8];
            word[..rest.len()].copy_from_slice(rest);
            self.add(u64::from_le_bytes(word) ^ ((rest.len() as u64) << 59));
        }
    }

    #[inline]
    fn write_u8(&mut self, n: u8) {
        self.add(u64::from(n));
    }

    #[inline]
    fn write_u32(&mut self, n: u32) {
        self.add(u64::from(n));
    }

    #[inline]
    fn write_u64(&mut self, n: u64) {
        self.add(n);
    }

    #[inline]
    fn write_usize(&mut self, n: usize) {
        self.add(n as u64);
    }
}

/// Builds [`PairHasher`]s for a `HashMap`.
pub type PairBuildHasher = BuildHasherDefault<PairHasher>;

#[cfg(test)]
mod tests {
    use std::collections::HashSet;
    use std::hash::{BuildHasher, Hash};

    use super::*;

    fn bucket_of(key: (u64, u64), buckets: u64) -> u64 {
        PairBuildHasher::default().hash_one(key) % buckets
    }

    #[test]
    fn handle_pairs_spread_over_the_buckets() {
        // Pairs of a pile: body handles are small indices (generation in the high half), and
        // each body meets a few neighbours. 4,096 such keys in 8,192 buckets: a hash that
        // kept only low bits of the first handle would put them in at most 64 buckets; a
        // uniform one fills about 8,192 * (1 - e^-0.5) = 3,223. Requiring 2,900 (90% of
        // uniform) catches a weak mix without depending on luck.
        let keys: Vec<(u64, u64)> = (0..1024u64)
            .flat_map(|i| [1, 2, 32, 33].map(|d| (i | 1 << 32, (i + d) | 1 << 32)))
            .collect();
        let used: HashSet<u64> = keys.iter().map(|&k| bucket_of(k, 8192)).collect();
        assert!(used.len() > 2900, "{} buckets used", used.len());
        // Order matters: (a, b) and (b, a) are different keys.
        let mut h1 = PairHasher::default();
        (1u64, 2u64).hash(&mut h1);
        let mut h2 = PairHasher::default();
        (2u64, 1u64).hash(&mut h2);
        assert_ne!(h1.finish(), h2.finish());
    }
}
