//! Candidates this part cannot tell apart, found from the signatures themselves.
//!
//! Only what the baseline cannot absorb can be seen, so candidates are compared through their
//! unabsorbed spans `U_c = (I − P) S_c` (orthonormal bases `Q_c`):
//! - **pairwise**: the cosine of the smallest principal angle between `span U_a` and `span U_b`,
//!   the largest singular value of `Q_aᵀ Q_b` (for one-parameter candidates, the |cosine| of their
//!   unabsorbed columns). `a_within_b` is the smallest singular value when `dim a ≤ dim b`: 1 means
//!   every effect of `a` is also an effect of `b` (`tool_radius` ⊂ `tool_taper`, `c_index` ⊂
//!   `setup_error`). Pairs at or above [`EQUIVALENT_COS`] are reported as near-equivalent;
//! - **for a fitted effect** `e`: `cos(U e, span U_b) = ‖Q_bᵀ U e‖ / ‖U e‖`, how well candidate `b`
//!   reproduces the part of `e` that is visible (the `equivalence_corr` of the examples' keys).
//!
//! Threshold: a cosine of 0.98 leaves `√(1 − 0.98²) ≈ 20 %` of the visible effect unexplained by
//! the other candidate, which stays below the 2.5 σ detection limit unless the effect's visible
//! part exceeds 12.5 σ: at ordinary magnitudes the two cannot be told apart.

use crate::numerics::parallel::{map, Threads};
use std::borrow::Borrow;

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::effects::data::{Candidate, NamedColumns};
use crate::gap::span_gram::{SpanGram, GRAM_MIN_ROWS};
use crate::identify::solve::Factor;
use crate::numerics::order::sort_f64_descending;
use crate::parameter::Effect;

/// Cosine at or above which two candidates are reported as near-equivalent on this part.
pub const EQUIVALENT_COS: f64 = 0.98;

/// A pair of candidates that this part can hardly tell apart.
#[derive(Debug, Clone, Serialize)]
pub struct Equivalence {
    pub a: Effect,
    pub b: Effect,
    /// Cosine of the smallest principal angle between the unabsorbed spans.
    pub cosine: f64,
    /// Smallest singular value of `Q_aᵀ Q_b` when `dim a ≤ dim b` (1 = `a` inside `b`).
    pub a_within_b: Option<f64>,
}

/// Singular values of `Q_aᵀ Q_b` (cosines of the principal angles), largest first.
pub fn principal_cosines(qa: &DMatrix<f64>, qb: &DMatrix<f64>) -> Vec<f64> {
    if qa.ncols() == 0 || qb.ncols() == 0 {
        return Vec::new();
    }
    cosines_of(&(qa.transpose() * qb))
}

/// The singular values of `m = Q_aᵀ Q_b`, capped at 1, largest first.
fn cosines_of(m: &DMatrix<f64>) -> Vec<f64> {
    let mut sv: Vec<f64> = m.singular_values().iter().map(|v| v.min(1.0)).collect();
    sort_f64_descending(&mut sv);
    sv
}

/// `‖Q_bᵀ v‖ / ‖v‖`: how much of the vector `v` lies in the span with orthonormal basis `qb`.
pub fn cos_to_span(v: &DVector<f64>, qb: &DMatrix<f64>) -> f64 {
    let nv = v.norm();
    if nv == 0.0 || qb.ncols() == 0 {
        return 0.0;
    }
    ((qb.transpose() * v).norm() / nv).min(1.0)
}

/// Two candidates' unabsorbed spans compared, the smaller span first.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpanPair {
    /// The candidate of the smaller span (the first given when both are the same size).
    pub a: Effect,
    pub b: Effect,
    /// Cosine of the smallest principal angle (the largest singular value of `Q_aᵀ Q_b`).
    pub cosine: f64,
    /// The smallest singular value: 1 when every direction of `a`'s span lies in `b`'s.
    pub a_within_b: f64,
    /// Whether `a`'s span has fewer dimensions than `b`'s.
    pub smaller: bool,
}

/// [`SpanPair`] of the spans `x` and `y` (orthonormal bases); `None` when either is empty.
pub fn compare_spans(x: (Effect, &DMatrix<f64>), y: (Effect, &DMatrix<f64>)) -> Option<SpanPair> {
    // the smaller span first, so that `a_within_b` is meaningful
    let ((a, qa), (b, qb)) = if x.1.ncols() <= y.1.ncols() {
        (x, y)
    } else {
        (y, x)
    };
    span_pair(a, b, qa.ncols() < qb.ncols(), &principal_cosines(qa, qb))
}

/// The [`SpanPair`] of `a` and `b` (the smaller span first) from their principal cosines `sv`
/// (largest first); `None` when there are none.
fn span_pair(a: Effect, b: Effect, smaller: bool, sv: &[f64]) -> Option<SpanPair> {
    Some(SpanPair {
        a,
        b,
        cosine: *sv.first()?,
        a_within_b: *sv.last()?,
        smaller,
    })
}

/// Spans compared pair by pair ([`compare_spans`]); from [`GRAM_MIN_ROWS`] rows on, every
/// pair's `Q_aᵀ Q_b` read off one Gram matrix of them all ([`SpanGram`]: a dense scan's spans read
/// once, not once a pair).
pub struct SpanPairs<'a> {
    spans: Vec<(Effect, &'a DMatrix<f64>)>,
    gram: Option<SpanGram>,
}

impl<'a> SpanPairs<'a> {
    /// The spans (orthonormal bases of the same rows), their Gram matrix formed on `threads`
    /// threads when they are tall enough.
    pub fn new(spans: Vec<(Effect, &'a DMatrix<f64>)>, threads: Threads) -> Self {
        let rows = spans.first().map_or(0, |s| s.1.nrows());
        let gram = (rows >= GRAM_MIN_ROWS).then(|| {
            let bases: Vec<&DMatrix<f64>> = spans.iter().map(|s| s.1).collect();
            SpanGram::of(&bases, threads)
        });
        Self { spans, gram }
    }

    /// [`compare_spans`] of spans `i` and `j`.
    pub fn compare(&self, i: usize, j: usize) -> Option<SpanPair> {
        let Some(gram) = &self.gram else {
            return compare_spans(self.spans[i], self.spans[j]);
        };
        // the smaller span first, as compare_spans
        let (x, y) = if gram.width(i) <= gram.width(j) {
            (i, j)
        } else {
            (j, i)
        };
        if gram.width(x) == 0 {
            return None;
        }
        let sv = cosines_of(&gram.cross(x, y));
        span_pair(
            self.spans[x].0,
            self.spans[y].0,
            gram.width(x) < gram.width(y),
            &sv,
        )
    }
}

/// Orthonormal bases of the unabsorbed spans `(I − P) S_c` of `candidates` (`P` the projector on
/// the baseline design `baseline`), for the candidates that leave something visible.
pub fn unabsorbed_spans(
    baseline: &NamedColumns,
    candidates: &[Candidate],
) -> Vec<(Effect, DMatrix<f64>)> {
    let base = Factor::new(&baseline.matrix, None);
    candidates
        .iter()
        .map(|c| {
            let u = base.unabsorbed(&c.signature.matrix);
            (c.effect, Factor::of(u, None).basis)
        })
        .filter(|(_, q)| q.ncols() > 0)
        .collect()
}

/// All pairs whose unabsorbed spans (orthonormal bases, owned or borrowed: the diagnosis lends its
/// fits' without a copy) are within [`EQUIVALENT_COS`].
pub fn near_equivalent_pairs<M: Borrow<DMatrix<f64>> + Sync>(
    spans: &[(Effect, M)],
) -> Vec<Equivalence> {
    near_equivalent_pairs_on(spans, Threads::ONE)
}

/// [`near_equivalent_pairs`], each span's pairs with the later ones on its own (side by side on
/// `threads` threads), in the same order.
pub fn near_equivalent_pairs_on<M: Borrow<DMatrix<f64>> + Sync>(
    spans: &[(Effect, M)],
    threads: Threads,
) -> Vec<Equivalence> {
    let pairs = SpanPairs::new(
        spans.iter().map(|(e, q)| (*e, q.borrow())).collect(),
        threads,
    );
    let rows: Vec<usize> = (0..spans.len()).collect();
    map(threads, &rows, |&i| {
        (i + 1..spans.len())
            .filter_map(|j| pairs.compare(i, j))
            .filter(|p| p.cosine >= EQUIVALENT_COS)
            .map(|p| Equivalence {
                a: p.a,
                b: p.b,
                cosine: p.cosine,
                a_within_b: Some(p.a_within_b),
            })
            .collect::<Vec<_>>()
    })
    .into_iter()
    .flatten()
    .collect()
}
