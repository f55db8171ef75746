//! Every pair's `Q_aᵀ Q_b` of a dense scan's unabsorbed spans read off one Gram matrix.
//!
//! The pairwise comparison of [`crate::gap::equivalence`] needs `Q_aᵀ Q_b` for every pair of
//! candidates' spans. Taken pair by pair, each product reads both bases again, and a product
//! with a span of five columns or fewer (most of them: one parameter a candidate, or a few)
//! runs as short column updates, not as a blocked product. At a dense scan's 20,000 rows that was
//! 5 % of the diagnosis's CPU, at 200,000 rows half a second (issue 31). Here the spans are put
//! side by side, `Q = [Q_1 … Q_m]` (`n × K`), and `G = QᵀQ` (`K × K`) is formed once by row
//! blocks ([`crate::identify::solve::sum_over_row_blocks`]): each block's columns copied
//! together (in the cache), its `BᵀB` a blocked product, the blocks side by side on the threads
//! given, summed in the blocks' order (the same bits on any number of threads). `Q_aᵀ Q_b` is
//! then `G`'s block `(a, b)`.
//!
//! The sums are in another order than the pair-by-pair product's: equal to rounding. Only from
//! [`GRAM_MIN_ROWS`] rows on (a dense scan): below, the pairs keep the pair-by-pair product and
//! its bits (the built-in 100 points).

use nalgebra::DMatrix;

use crate::identify::solve::{sum_over_row_blocks, tr_mul};
use crate::numerics::parallel::Threads;

/// From this many rows on, the pairs' products come from one Gram matrix.
pub const GRAM_MIN_ROWS: usize = 4000;

/// The Gram matrix of spans put side by side, and where each span's columns start in it.
#[derive(Debug, Clone)]
pub struct SpanGram {
    /// `QᵀQ`, `K × K`.
    g: DMatrix<f64>,
    /// Span `i`'s columns are `offsets[i]..offsets[i + 1]`.
    offsets: Vec<usize>,
}

impl SpanGram {
    /// The Gram matrix of `spans` (each `n × k_i`, the same `n`), by row blocks side by side on
    /// `threads` threads.
    pub fn of(spans: &[&DMatrix<f64>], threads: Threads) -> Self {
        let mut offsets = Vec::with_capacity(spans.len() + 1);
        offsets.push(0);
        for q in spans {
            offsets.push(offsets.last().copied().unwrap_or(0) + q.ncols());
        }
        let k = offsets.last().copied().unwrap_or(0);
        let n = spans.first().map_or(0, |q| q.nrows());
        assert!(
            spans.iter().all(|q| q.nrows() == n),
            "SpanGram::of: spans of {:?} rows",
            spans.iter().map(|q| q.nrows()).collect::<Vec<_>>()
        );
        let g = sum_over_row_blocks(n, k, threads, |r0, rows| {
            let mut b = DMatrix::<f64>::zeros(rows, k);
            for (q, &at) in spans.iter().zip(&offsets) {
                b.columns_mut(at, q.ncols()).copy_from(&q.rows(r0, rows));
            }
            tr_mul(&b, &b)
        });
        Self { g, offsets }
    }

    /// The number of columns of span `i`.
    pub fn width(&self, i: usize) -> usize {
        self.offsets[i + 1] - self.offsets[i]
    }

    /// `Q_aᵀ Q_b` (`k_a × k_b`).
    pub fn cross(&self, a: usize, b: usize) -> DMatrix<f64> {
        self.g
            .view(
                (self.offsets[a], self.offsets[b]),
                (self.width(a), self.width(b)),
            )
            .into_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `G`'s blocks are the pair-by-pair products to rounding (1e-13 of the product of the
    /// columns' norms, 1 here: orthonormal bases), on spans of 1, 3 and 7 columns over 9,000
    /// rows (three blocks, the last short), and the same bits on 1 and 3 threads.
    #[test]
    fn the_gram_blocks_are_the_pairs_products() {
        let n = 9000;
        let f =
            |i: usize, j: usize| ((i * 31 + j * 17) % 23) as f64 - 11.0 + (i as f64 * 0.01).sin();
        let orthonormal = |k: usize, shift: usize| {
            let a = DMatrix::from_fn(n, k, |i, j| f(i, j + shift));
            a.qr().q()
        };
        let spans = [orthonormal(1, 0), orthonormal(3, 2), orthonormal(7, 5)];
        let refs: Vec<&DMatrix<f64>> = spans.iter().collect();
        let gram = SpanGram::of(&refs, Threads::ONE);
        for a in 0..3 {
            assert_eq!(gram.width(a), spans[a].ncols());
            for b in 0..3 {
                let direct = spans[a].transpose() * &spans[b];
                let got = gram.cross(a, b);
                assert!(
                    (&got - &direct).amax() < 1e-13,
                    "({a}, {b}): {}",
                    (&got - &direct).amax()
                );
            }
        }
        let three = SpanGram::of(&refs, Threads::new(3));
        assert_eq!(three.g, gram.g);
    }
}
