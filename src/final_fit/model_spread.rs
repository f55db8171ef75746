//! What the choice of model can move the location errors by: the spread of their estimates over
//! the candidate models, weighted by the evidence of each (issue 29 item 3).
//!
//! The final answer is fitted with one model (the baseline for `none`, the location errors and
//! the named effect, or the structure as a correlated error). An effect below the detection limit,
//! or one the verdict got wrong, still moves the location errors: the part of it their columns
//! absorb is invisible in the residual, but the fits of the other models show it. Bayesian model
//! averaging (Hoeting et al., *Statistical Science* 14(4), 1999, eq. 1-2) gives the variance of
//! an estimate over models `M_c` as the within-model variance plus
//! `Σ_c w_c (β̂_c − β̄)²`; here the answer keeps the chosen model's estimate `β̂_0` (the diagnosis
//! decides it), so the added variance is the weighted mean square of the other models' estimates
//! about it, `v_j = Σ_c w_c (β̂_{c,j} − β̂_{0,j})²`, and each identified location error's std
//! becomes `√(std_j² + v_j)`.
//!
//! Models: the baseline `A` and `[A | S_c]` for every candidate `c` (its signature columns), each
//! fitted by least squares on the points used; the chosen model's own linear fit is `β̂_0`. The
//! weights are BIC's (Schwarz 1978): `w_c ∝ exp(−½ (RSS_c/σ² + q_c ln n))`, `q_c` the columns
//! the model adds, σ the part's noise. Unidentified parameters (no std) are left as they are.

use std::collections::BTreeMap;

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::effects::data::Candidate;
use crate::identify::solve::{hstack, Factor};

/// The model spread of each location error.
#[derive(Debug, Clone, Serialize, Default)]
pub struct ModelSpread {
    /// `√v_j` per parameter (its unit).
    pub std: BTreeMap<String, f64>,
    /// The weight of each model whose weight is at least 1 % (`baseline` or an effect id).
    pub weights: BTreeMap<String, f64>,
}

/// Least-squares estimate of the first `p` coefficients and the RSS of `x` on `y`.
fn fit(x: &DMatrix<f64>, y: &DVector<f64>, p: usize) -> (DVector<f64>, f64) {
    let scale: Vec<f64> = x.column_iter().map(|c| c.norm().max(1e-300)).collect();
    let f = Factor::new(x, Some(&scale));
    let beta = &f.pinv * y;
    let rss = f.unabsorbed_vec(y).norm_squared();
    (beta.rows(0, p).into_owned(), rss)
}

/// The spread over the models of the location errors (`a`: their columns, `names` in order)
/// fitted to `y` on the rows `used`, about the chosen model's estimate (`chosen`: the columns it
/// adds to `a`, none for the baseline), with the part's noise `sigma` (mm).
pub fn model_spread(
    a: &DMatrix<f64>,
    names: &[String],
    y: &[f64],
    used: &[usize],
    candidates: &[Candidate],
    chosen: Option<&DMatrix<f64>>,
    sigma: f64,
) -> ModelSpread {
    let p = a.ncols();
    let n = used.len();
    if n <= p || sigma <= 0.0 || !sigma.is_finite() {
        return ModelSpread::default();
    }
    let au = a.select_rows(used);
    let yu = DVector::from_iterator(n, used.iter().map(|&i| y[i]));
    let (b0, _) = match chosen {
        Some(s) => fit(&hstack(&au, &s.select_rows(used)), &yu, p),
        None => fit(&au, &yu, p),
    };
    let ln_n = (n as f64).ln();
    let mut models: Vec<(String, DVector<f64>, f64)> = Vec::new();
    let (b, rss) = fit(&au, &yu, p);
    models.push(("baseline".into(), b, rss / (sigma * sigma)));
    let base_rank = Factor::new(&au, None).rank;
    for c in candidates {
        let s = c.signature.matrix.select_rows(used);
        let x = hstack(&au, &s);
        if x.nrows() <= x.ncols() {
            continue;
        }
        let (b, rss) = fit(&x, &yu, p);
        let added = Factor::new(&x, None).rank.saturating_sub(base_rank);
        models.push((
            c.effect.id().to_string(),
            b,
            rss / (sigma * sigma) + added as f64 * ln_n,
        ));
    }
    let best = models.iter().map(|m| m.2).fold(f64::INFINITY, f64::min);
    let raw: Vec<f64> = models.iter().map(|m| (-0.5 * (m.2 - best)).exp()).collect();
    let total: f64 = raw.iter().sum();
    let mut out = ModelSpread::default();
    for (j, name) in names.iter().enumerate().take(p) {
        let v: f64 = models
            .iter()
            .zip(&raw)
            .map(|((_, b, _), w)| w / total * (b[j] - b0[j]).powi(2))
            .sum();
        out.std.insert(name.clone(), v.sqrt());
    }
    for ((id, _, _), w) in models.iter().zip(&raw) {
        if w / total >= 0.01 {
            out.weights.insert(id.clone(), w / total);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::data::NamedColumns;
    use crate::numerics::random::Sampler;
    use crate::parameter::{Effect, ParamId};

    /// An effect the baseline cannot see apart from a location error moves that error; the
    /// model it is fitted in has the weight, and the spread is the move.
    #[test]
    fn a_hidden_effect_widens_what_it_moves() {
        let n = 60;
        let t: Vec<f64> = (0..n).map(|i| i as f64 / n as f64).collect();
        let a = DMatrix::from_fn(n, 2, |i, j| if j == 0 { 1.0 } else { t[i] });
        // the effect: half a constant (absorbed) plus a bump the baseline cannot follow
        let e: Vec<f64> = t
            .iter()
            .map(|x| 0.5 + (-(x - 0.5f64).powi(2) / 0.005).exp())
            .collect();
        let mut rng = Sampler::new(1);
        let y: Vec<f64> = e.iter().map(|v| 0.2 * v + 0.01 * rng.normal()).collect();
        let used: Vec<usize> = (0..n).collect();
        let c = Candidate {
            effect: Effect::ToolRadius,
            signature: NamedColumns::try_new(
                vec![ParamId::Effect {
                    effect: Effect::ToolRadius,
                    index: 0,
                }],
                DMatrix::from_column_slice(n, 1, &e),
            )
            .unwrap(),
            family: None,
        };
        let s = model_spread(
            &a,
            &["c".into(), "m".into()],
            &y,
            &used,
            std::slice::from_ref(&c),
            None,
            0.01,
        );
        assert!(s.weights["tool_radius"] > 0.99, "{:?}", s.weights);
        // the baseline's intercept holds 0.2·(0.5 + the bump's mean) − the fit with the effect's
        // 0: its spread is that offset, about 0.1 + 0.2·0.125
        assert!(s.std["c"] > 0.09, "{:?}", s.std);
        // chosen = the effect's model: the spread about it is small
        let s = model_spread(
            &a,
            &["c".into(), "m".into()],
            &y,
            &used,
            std::slice::from_ref(&c),
            Some(&c.signature.matrix),
            0.01,
        );
        assert!(s.std["c"] < 0.01, "{:?}", s.std);
    }
}
