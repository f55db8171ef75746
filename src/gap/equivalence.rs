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
    let m = qa.transpose() * qb;
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
    let sv = principal_cosines(qa, qb);
    Some(SpanPair {
        a,
        b,
        cosine: *sv.first()?,
        a_within_b: *sv.last()?,
        smaller: qa.ncols() < qb.ncols(),
    })
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
            (c.effect, Factor::new(&u, None).basis)
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
    let rows: Vec<usize> = (0..spans.len()).collect();
    map(threads, &rows, |&i| {
        let (na, qa) = &spans[i];
        spans[i + 1..]
            .iter()
            .filter_map(|(nb, qb)| compare_spans((*na, qa.borrow()), (*nb, qb.borrow())))
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
