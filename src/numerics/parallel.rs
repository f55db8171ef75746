//! A map over independent items on a given number of threads (issue 31: a scan's candidates are
//! fitted and its model's signatures computed side by side on the cores there are).
//!
//! The thread count is a value the caller passes ([`Threads`]), never read from the machine here:
//! the CLI gives the cores it has, `validate` one a part (its parts are already spread over its
//! threads), the wasm build always one (`wasm32-unknown-unknown` has no threads; the map is then
//! the plain sequential one). Each item is computed by the same code whatever the count and the
//! results keep the items' order, so the output is the same bit for bit on 1 or 8 threads.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};

/// How many threads a stage may use (at least 1; 1 = the calling thread alone).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Threads(usize);

impl Threads {
    /// The calling thread alone.
    pub const ONE: Threads = Threads(1);

    /// `n` threads (0 counts as 1).
    pub fn new(n: usize) -> Self {
        Threads(n.max(1))
    }

    pub fn get(self) -> usize {
        self.0
    }
}

impl Default for Threads {
    fn default() -> Self {
        Threads::ONE
    }
}

/// `items.iter().map(f).collect()`, the items shared out between `threads` threads as each
/// becomes free (their costs differ: a family of 54 members beside a one-column candidate).
pub fn map<T, R, F>(threads: Threads, items: &[T], f: F) -> Vec<R>
where
    T: Sync,
    R: Send,
    F: Fn(&T) -> R + Sync,
{
    let workers = threads.get().min(items.len());
    if workers <= 1 || cfg!(target_arch = "wasm32") {
        return items.iter().map(f).collect();
    }
    // runs of consecutive items, taken as a thread becomes free: one item at a time for a few
    // costly items (a stage's candidates), runs for many cheap ones (a scan's 200,000 points:
    // an item at a time, the results' sort by index had been a serial tail of 50 ms, issue 31)
    let run = (items.len() / (workers * RUNS_PER_THREAD)).max(1);
    let next = AtomicUsize::new(0);
    let work = || {
        let mut done: Vec<(usize, Vec<R>)> = Vec::new();
        loop {
            let first = next.fetch_add(run, Ordering::Relaxed);
            if first >= items.len() {
                return done;
            }
            let end = items.len().min(first + run);
            done.push((first, items[first..end].iter().map(&f).collect()));
        }
    };
    let mut runs: Vec<(usize, Vec<R>)> = std::thread::scope(|s| {
        let others: Vec<_> = (1..workers).map(|_| s.spawn(work)).collect();
        let mut all = work();
        for h in others {
            match h.join() {
                Ok(part) => all.extend(part),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        }
        all
    });
    runs.sort_unstable_by_key(|(first, _)| *first);
    let mut out = Vec::with_capacity(items.len());
    for (_, mut r) in runs {
        out.append(&mut r);
    }
    out
}

/// Runs of items a thread takes at a time in [`map`]: about this many runs a thread, so that
/// the last runs still balance the threads.
const RUNS_PER_THREAD: usize = 64;

/// [`map`] over items `f` may change (each item is handed to one thread at a time): e.g. disjoint
/// blocks of one output, each written by the item that owns it.
pub fn map_mut<T, R, F>(threads: Threads, items: &mut [T], f: F) -> Vec<R>
where
    T: Send,
    R: Send,
    F: Fn(&mut T) -> R + Sync,
{
    let cells: Vec<Mutex<&mut T>> = items.iter_mut().map(Mutex::new).collect();
    map(threads, &cells, |cell| {
        f(&mut cell.lock().unwrap_or_else(PoisonError::into_inner))
    })
}

/// `(a(), b())`, `b` on another thread when `threads` allows it (`a` on the calling thread:
/// it may hold what cannot cross threads, a progress sink).
pub fn join<A, B, RA, RB>(threads: Threads, a: A, b: B) -> (RA, RB)
where
    A: FnOnce() -> RA,
    B: FnOnce() -> RB + Send,
    RB: Send,
{
    if threads.get() <= 1 || cfg!(target_arch = "wasm32") {
        return (a(), b());
    }
    std::thread::scope(|s| {
        let hb = s.spawn(b);
        let ra = a();
        match hb.join() {
            Ok(rb) => (ra, rb),
            Err(panic) => std::panic::resume_unwind(panic),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same results in the same order on 1, 2 and 7 threads, items of unequal cost.
    #[test]
    fn the_map_keeps_the_order_whatever_the_threads() {
        let items: Vec<u64> = (0..50).collect();
        let f = |&k: &u64| (0..(k % 7) * 1000).fold(k, |a, x| a.wrapping_mul(31).wrapping_add(x));
        let one = map(Threads::ONE, &items, f);
        assert_eq!(one, items.iter().map(f).collect::<Vec<_>>());
        assert_eq!(map(Threads::new(2), &items, f), one);
        assert_eq!(map(Threads::new(7), &items, f), one);
        // many items: taken in runs (10,001 items on 3 threads, runs of 52, the last short)
        let many: Vec<u64> = (0..10_001).collect();
        let all = map(Threads::ONE, &many, f);
        assert_eq!(map(Threads::new(3), &many, f), all);
        assert_eq!(map(Threads::new(2), &many, f), all);
        assert_eq!(map(Threads::new(3), &[] as &[u64], f), Vec::<u64>::new());
        assert_eq!(join(Threads::new(2), || 1, || 2), (1, 2));
        // each item changed by its own call, the results in the items' order
        let mut changed: Vec<u64> = items.clone();
        let got = map_mut(Threads::new(3), &mut changed, |k| {
            *k += 1;
            f(k)
        });
        assert_eq!(changed, items.iter().map(|k| k + 1).collect::<Vec<_>>());
        assert_eq!(got, changed.iter().map(f).collect::<Vec<_>>());
    }
}
