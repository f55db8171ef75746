//! Cross-validation folds: points withheld from the fit, by curve and by region of the S.
//!
//! Two schemes, both used, so every point is withheld twice:
//! - **by curve**: 4 folds, each withholds one curve (`A_Z11`, `A_Z25`, `B_Z11`, `B_Z25`) and fits
//!   the other three; an effect must predict a curve it has not seen (e.g. the Z25 curve of the
//!   same surface, at another contact height);
//! - **by region**: 5 folds, each withholds one band of `u` ([`crate::gap::regions::Region`]) on all
//!   curves; an effect must predict a part of the S it has not seen (steps at reversals, trends).
//!
//! The baseline design restricted to each training set is factorised once per fold
//! ([`FoldFactor`]) and reused for every candidate.

use nalgebra::{DMatrix, DVector};

use crate::effects::data::PointMeta;
use crate::effects::data::{curve_sequences, is_scan};
use crate::gap::regions::Region;
use crate::identify::solve::Factor;
use crate::numerics::order::sort_by_key_f64;
use crate::numerics::parallel::{map, Threads};
use crate::part::Surface;

/// One fold: which points are fitted and which are withheld, with the baseline factorised on the
/// fitted ones.
#[derive(Debug, Clone)]
pub struct FoldFactor {
    pub name: String,
    pub train: Vec<usize>,
    pub test: Vec<usize>,
    pub base: Factor,
    pub a_test: DMatrix<f64>,
    pub y_train: DVector<f64>,
    pub y_test: DVector<f64>,
    /// Training deviations minus their projection on the baseline.
    pub r0_train: DVector<f64>,
    /// The training deviations' products with the baseline's basis, `Qᵀy` (its least-squares
    /// solution is `base.solve_products` of them).
    pub qty_train: DVector<f64>,
}

/// The withheld sets: `(name, test indices)`, curve folds then region folds; empty ones skipped.
pub fn withheld_sets(points: &[PointMeta]) -> Vec<(String, Vec<usize>)> {
    let mut out: Vec<(String, Vec<usize>)> = if is_scan(points) {
        height_bands(points)
    } else {
        curve_sequences(points)
            .into_iter()
            .map(|(c, idx)| (format!("curve:{c}"), idx))
            .collect()
    };
    for reg in Region::ALL {
        let idx: Vec<usize> = (0..points.len())
            .filter(|&i| Region::of_u(points[i].u) == reg)
            .collect();
        if !idx.is_empty() {
            out.push((format!("region:{}", reg.name()), idx));
        }
    }
    out
}

/// A scan's lines withheld in two bands a surface, the lower and the upper half of its lines by
/// mean contact height (`band:A_low`, …): as many folds as the four curves of a discrete layout,
/// whatever the number of lines.
fn height_bands(points: &[PointMeta]) -> Vec<(String, Vec<usize>)> {
    let mut out = Vec::new();
    for s in Surface::BOTH {
        let mut lines: Vec<(f64, Vec<usize>)> = curve_sequences(points)
            .into_iter()
            .filter(|(_, idx)| idx.first().is_some_and(|&i| points[i].surface == s))
            .map(|(_, idx)| {
                let h = idx.iter().map(|&i| points[i].h).sum::<f64>() / idx.len() as f64;
                (h, idx)
            })
            .collect();
        if lines.is_empty() {
            continue;
        }
        sort_by_key_f64(&mut lines, |l| l.0);
        let half = lines.len().div_ceil(2);
        for (name, part) in [("low", &lines[..half]), ("high", &lines[half..])] {
            let mut idx: Vec<usize> = part.iter().flat_map(|l| l.1.iter().copied()).collect();
            if idx.is_empty() {
                continue;
            }
            idx.sort_unstable();
            out.push((format!("band:{}_{name}", s.name()), idx));
        }
    }
    out
}

/// Factorises the baseline on each fold's training set, the folds side by side on `threads`
/// threads (the same factors). Folds whose training set has fewer than `min_train` points, or
/// that withhold every point, are skipped.
pub fn build_folds(
    points: &[PointMeta],
    a: &DMatrix<f64>,
    y: &DVector<f64>,
    min_train: usize,
    threads: Threads,
) -> Vec<FoldFactor> {
    let n = points.len();
    map(threads, &withheld_sets(points), |(name, test)| {
        let mut is_test = vec![false; n];
        for &i in test {
            is_test[i] = true;
        }
        let train: Vec<usize> = (0..n).filter(|&i| !is_test[i]).collect();
        if train.len() < min_train || test.is_empty() {
            return None;
        }
        // (the training rows factorised in place, not copied again)
        let base = Factor::of(a.select_rows(&train), None);
        let y_train = DVector::from_iterator(train.len(), train.iter().map(|&i| y[i]));
        let y_test = DVector::from_iterator(test.len(), test.iter().map(|&i| y[i]));
        let qty_train = base.basis.tr_mul(&y_train);
        let r0_train = &y_train - &base.basis * &qty_train;
        Some(FoldFactor {
            name: name.clone(),
            a_test: a.select_rows(test),
            train,
            test: test.clone(),
            base,
            y_train,
            y_test,
            r0_train,
            qty_train,
        })
    })
    .into_iter()
    .flatten()
    .collect()
}
