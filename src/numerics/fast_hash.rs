//! A hasher for the keys of small integers and float bits that a dense scan deduplicates by the
//! hundred thousand (the reversal grid's sites, issue 31), where the standard library's SipHash
//! (built to resist chosen keys, which these are not) was a third of the work.
//!
//! The multiply-rotate mix of Firefox's and rustc's "FxHash": per word,
//! `h = (rotl(h, 5) ⊕ word) · K` with `K = 0x517c_c1b7_2722_0a95`. Not for keys from outside.

use std::hash::{BuildHasherDefault, Hasher};

/// The mixing constant (rustc-hash's, from the golden ratio).
const K: u64 = 0x517c_c1b7_2722_0a95;

/// The hasher ([`FastHashMap`] builds one per key).
#[derive(Debug, Default, Clone, Copy)]
pub struct FastHasher {
    hash: u64,
}

impl FastHasher {
    fn add(&mut self, word: u64) {
        self.hash = (self.hash.rotate_left(5) ^ word).wrapping_mul(K);
    }
}

impl Hasher for FastHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.add(u64::from_le_bytes(word));
        }
    }

    fn write_u64(&mut self, i: u64) {
        self.add(i);
    }

    fn write_usize(&mut self, i: usize) {
        self.add(i as u64);
    }

    fn finish(&self) -> u64 {
        self.hash
    }
}

/// A `HashMap` with [`FastHasher`].
pub type FastHashMap<K, V> = std::collections::HashMap<K, V, BuildHasherDefault<FastHasher>>;

#[cfg(test)]
mod tests {
    use super::*;

    /// Keys as the reversal grid makes them (surface, step, length bits) land in distinct
    /// entries: 100,000 distinct keys, 100,000 entries, each found again with its value.
    #[test]
    fn distinct_keys_stay_distinct() {
        let mut m: FastHashMap<(usize, usize, u64), usize> = FastHashMap::default();
        let key = |i: usize| (i % 2, i / 7, (i as f64 * 0.013 + 1.0).to_bits());
        for i in 0..100_000 {
            assert_eq!(m.insert(key(i), i), None);
        }
        assert_eq!(m.len(), 100_000);
        assert!((0..100_000).all(|i| m[&key(i)] == i));
    }
}
