//! A small bounded memo inside values their callers hold (issue 28: no per-thread or
//! process-wide cache): the point models of an analysis session
//! (`crate::analysis::Session`) and the final fit's eigen-decompositions for a point set
//! ([`crate::final_fit::structure::Decompositions`]). Keys are compared by a predicate
//! (bit-exact comparisons of floating-point inputs); the most recently used entry is first, the
//! least recently used is dropped beyond the capacity.

use std::sync::Arc;

/// A bounded list of computed values, most recently used first.
pub(crate) struct Memo<K, V> {
    entries: Vec<(K, Arc<V>)>,
    capacity: usize,
}

impl<K, V> Memo<K, V> {
    pub(crate) const fn new(capacity: usize) -> Self {
        Self {
            entries: Vec::new(),
            capacity,
        }
    }

    /// The value whose key satisfies `is`, moved to the front.
    pub(crate) fn find(&mut self, is: impl Fn(&K) -> bool) -> Option<Arc<V>> {
        let i = self.entries.iter().position(|(k, _)| is(k))?;
        let e = self.entries.remove(i);
        let v = Arc::clone(&e.1);
        self.entries.insert(0, e);
        Some(v)
    }

    /// Keeps `value` in front, dropping the least recently used beyond the capacity.
    pub(crate) fn insert(&mut self, key: K, value: Arc<V>) {
        self.entries.insert(0, (key, value));
        self.entries.truncate(self.capacity);
    }

    /// Drops every entry.
    pub(crate) fn clear(&mut self) {
        self.entries.clear();
    }

    /// Number of entries kept.
    pub(crate) fn len(&self) -> usize {
        self.entries.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_memo_keeps_the_most_recent_up_to_its_capacity() {
        let mut m: Memo<u32, u32> = Memo::new(2);
        m.insert(1, Arc::new(10));
        m.insert(2, Arc::new(20));
        assert_eq!(m.find(|k| *k == 1).as_deref(), Some(&10));
        m.insert(3, Arc::new(30));
        // 2 was the least recently used.
        assert!(m.find(|k| *k == 2).is_none());
        assert_eq!(m.entries.iter().map(|e| e.0).collect::<Vec<_>>(), [3, 1]);
        m.clear();
        assert_eq!(m.len(), 0);
    }
}
