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
//! Models: the answer's (`A`, or `[A | S_0]` with the named effect's columns `S_0`), the
//! baseline `A`, `[A | S_c]` for every other candidate `c` (its signature columns) and, for a
//! named answer, `[A | S_0 | S_c]` (the named effect with another: a tool's wear with a run-in is
//! a radius change and a wear), and `[A | N_f]` for every family `f` of
//! [`crate::effects::nuisance`] (shapes no candidate names: a probe's lobing, the part drifting
//! on the CMM), each fitted by least squares on the points used, and, beside the answer's model
//! (not `unexplained`'s, whose residual is the structure's), the linear axes' error motions
//! pooled into one random effect ([`crate::final_fit::pooled`]: its estimate by generalised
//! least squares, its score its likelihood's gain plus `ln n` over the answer's, and its own
//! covariance beyond the answer's model's added at its weight: a pitch error named as its axis's
//! scale leaves its curvature). `β̂_0` is the
//! answer's own linear estimate: by generalised least squares in the whitened problem when the
//! answer has the structure as a correlated error (`unexplained`), so that the spread is about
//! the value reported. The weights are BIC's (Schwarz 1978): `w_c ∝ π_c exp(−½ (RSS_c/σ² +
//! q_c ln n))`, `q_c` the columns the model adds, σ the part's noise, with the prior `π` half on
//! the answer's model (the diagnosis chose it) and half shared by the alternatives, the `m`
//! nuisance families sharing one candidate's share (each `1/m` of it: they are what no candidate
//! is, not `m` more effects the part could have). The spread's
//! whole second moment `Σ_c w_c (β̂_c − β̂_0)(β̂_c − β̂_0)ᵀ` is added to the answer's covariance.
//! Unidentified parameters (no std) are left as they are.

use std::collections::BTreeMap;

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::effects::data::Candidate;
use crate::effects::nuisance::Nuisance;
use crate::final_fit::pooled::pooled_fit;
use crate::identify::added_fits::{AddedFit, AddedFits};
use crate::identify::correlated::Whitener;
use crate::identify::solve::{hstack, Factor};
use crate::numerics::parallel::{map, Threads};

/// The id of the pooled error motions' model among the spread's weights.
pub const POOLED_ID: &str = "error_motions";

/// The model spread of each location error.
#[derive(Debug, Clone, Serialize, Default)]
pub struct ModelSpread {
    /// `√v_j` per parameter (its unit).
    pub std: BTreeMap<String, f64>,
    /// The weight of each model whose weight is at least 1 % (`baseline`, `answer` (the named
    /// answer's model), an effect id, `answer+<id>`: the answer's effect with another, a
    /// nuisance family's id, or [`POOLED_ID`]: the error motions pooled).
    pub weights: BTreeMap<String, f64>,
    /// The whole second moment `Σ_c w_c (β̂_c − β̂_0)(β̂_c − β̂_0)ᵀ`, with the pooled model's own
    /// covariance beyond the answer's model's at its weight (units² of the
    /// parameters), rows and columns in the order of the names given; `std` is the root of its
    /// diagonal.
    #[serde(skip)]
    pub covariance: Vec<Vec<f64>>,
}

/// The answer the spread is about: the columns its model adds to the location errors' (the named
/// effect's; none for the baseline and `unexplained`), and its whitener when it has the structure
/// as a correlated error.
#[derive(Debug, Clone, Copy, Default)]
pub struct Answer<'a> {
    pub chosen: Option<&'a DMatrix<f64>>,
    pub whitener: Option<&'a Whitener>,
}

/// A model's least-squares fit: the first `p` coefficients, the RSS and the rank of its columns.
#[derive(Clone)]
struct Fit {
    beta: DVector<f64>,
    rss: f64,
    rank: usize,
}

/// The norm each column of a model is measured against (the rank decided on them).
fn column_norms(x: &DMatrix<f64>) -> Vec<f64> {
    x.column_iter().map(|c| c.norm().max(1e-300)).collect()
}

/// `x` factorised with its columns measured against their norms ([`column_norms`]), in place
/// (a model's design is built for its fit: a copy had been 14 MB a model at 200,000 points).
fn factor(x: DMatrix<f64>) -> Factor {
    let scale = column_norms(&x);
    Factor::of(x, Some(&scale))
}

/// [`factor`] of a design given up, a tall one's row blocks side by side on `threads` threads
/// ([`Factor::of_on`]: the same numbers, a column alone by its norm as [`Factor::new`] does):
/// the factorisations outside the models' map, which had run on one thread (a dense scan's
/// 200,000 rows, issue 31).
fn factor_on(x: DMatrix<f64>, threads: Threads) -> Factor {
    let scale = column_norms(&x);
    Factor::of_on(x, Some(&scale), threads)
}

/// The least-squares [`Fit`] of `[x | s]` on `y` (`shared`: `x` and `y`, factorised once, on a
/// tall design: [`AddedFits`]), its first `p` coefficients kept.
fn fit_added(
    x: &DMatrix<f64>,
    shared: Option<&AddedFits>,
    s: &DMatrix<f64>,
    y: &DVector<f64>,
    p: usize,
) -> Fit {
    match shared {
        Some(f) if f.takes(s.ncols()) => {
            let AddedFit { beta, rss, rank } = f.fit(s, &column_norms(s));
            Fit {
                beta: beta.rows(0, p).into_owned(),
                rss,
                rank,
            }
        }
        _ => fit(hstack(x, s), y, p),
    }
}

/// The least-squares [`Fit`] of `x` on `y`, its first `p` coefficients kept.
fn fit(x: DMatrix<f64>, y: &DVector<f64>, p: usize) -> Fit {
    fit_on(&factor(x), y, p)
}

/// The least-squares [`Fit`] on `y` of the columns factorised in `f`, its first `p`
/// coefficients kept.
fn fit_on(f: &Factor, y: &DVector<f64>, p: usize) -> Fit {
    let beta = f.solve(y);
    let rss = f.unabsorbed_vec(y).norm_squared();
    Fit {
        beta: beta.rows(0, p).into_owned(),
        rss,
        rank: f.rank,
    }
}

/// The spread over the models of the location errors (`a`: their columns, `names` in order)
/// fitted to `y` on the rows `used`, about the chosen model's estimate (`chosen`: the columns it
/// adds to `a`, none for the baseline), with the part's noise `sigma` (mm), over the models of
/// the `candidates` and of the `nuisance` families; their fits side by side on `threads` threads
/// (the same numbers).
#[allow(clippy::too_many_arguments)]
pub fn model_spread(
    a: &DMatrix<f64>,
    names: &[String],
    y: &[f64],
    used: &[usize],
    candidates: &[Candidate],
    nuisance: &[Nuisance],
    answer: Answer,
    sigma: f64,
    threads: Threads,
) -> ModelSpread {
    let Answer { chosen, whitener } = answer;
    let (pooled, nuisance): (Vec<&Nuisance>, Vec<&Nuisance>) =
        nuisance.iter().partition(|f| f.pooled);
    let p = a.ncols();
    let n = used.len();
    if n <= p || sigma <= 0.0 || !sigma.is_finite() {
        return ModelSpread::default();
    }
    // the answer's estimate: generalised least squares in the whitened problem when the answer
    // has a correlated error; without one it is the answer's own fit below (the same columns on
    // the same rows, factorised once)
    let whitened_b0 = whitener.map(|w| {
        let white = |m: &DMatrix<f64>| w.apply(m).select_rows(used);
        let yfull = DMatrix::from_column_slice(y.len(), 1, y);
        let wy = DVector::from_iterator(n, white(&yfull).iter().copied());
        match chosen {
            Some(s) => fit_on(&factor_on(hstack(&white(a), &white(s)), threads), &wy, p),
            None => fit_on(&factor_on(white(a), threads), &wy, p),
        }
        .beta
    });
    let au = a.select_rows(used);
    let yu = DVector::from_iterator(n, used.iter().map(|&i| y[i]));
    let ln_n = (n as f64).ln();
    // each model's columns factorised once: its estimate, RSS and rank from the same fit
    // the baseline's factorisation, kept for the pooled error motions beside a baseline answer
    let base_factor = factor_on(au.clone(), threads);
    let base = fit_on(&base_factor, &yu, p);
    let base_rank = base.rank;
    // a model's BIC: its RSS over σ², `ln n` for each column it adds to the location errors'
    let bic = |f: &Fit| f.rss / (sigma * sigma) + f.rank.saturating_sub(base_rank) as f64 * ln_n;
    let mut answer_score = bic(&base);
    // (id, estimate, BIC) of every model; the answer's own first
    let mut models: Vec<(String, DVector<f64>, f64)> = Vec::new();
    // a model of `cols` columns on the `n` rows
    let mut push = |id: String, cols: usize, f: Fit| {
        if n <= cols {
            return;
        }
        let score = bic(&f);
        models.push((id, f.beta, score));
    };
    let answer = chosen.map_or_else(|| au.clone(), |s| hstack(&au, &s.select_rows(used)));
    // a named answer's factorisation, kept for the pooled error motions beside it
    let mut answer_factor = None;
    let (answer_rank, ols_b0) = match chosen {
        Some(_) => {
            let fa = factor_on(answer.clone(), threads);
            let f = fit_on(&fa, &yu, p);
            let (rank, beta) = (f.rank, f.beta.clone());
            answer_score = bic(&f);
            push("answer".into(), answer.ncols(), f);
            push("baseline".into(), p, base);
            answer_factor = Some(fa);
            (rank, beta)
        }
        None => {
            let beta = base.beta.clone();
            push("baseline".into(), p, base);
            (base_rank, beta)
        }
    };
    let b0 = whitened_b0.unwrap_or(ols_b0);
    // the location errors' columns and the answer's factorised once for all the alternatives
    // beside them (a dense scan: [`AddedFits`]), side by side
    let (shared_base, shared_answer) = crate::numerics::parallel::join(
        threads,
        || AddedFits::new(&au, &column_norms(&au), &yu),
        || {
            chosen
                .is_some()
                .then(|| AddedFits::new(&answer, &column_norms(&answer), &yu))
                .flatten()
        },
    );
    // each candidate's fits (side by side on the threads given), taken in the candidates' order
    let alts: Vec<(String, &DMatrix<f64>)> = candidates
        .iter()
        .map(|c| (c.effect.id().to_string(), &c.signature.matrix))
        .chain(nuisance.iter().map(|s| (s.id.clone(), &s.columns)))
        .collect();
    let fitted = map(threads, &alts, |(_, m)| {
        let s = m.select_rows(used);
        let single = au.ncols() + s.ncols();
        let fs = fit_added(&au, shared_base.as_ref(), &s, &yu, p);
        // with the baseline as the answer, the answer with the candidate is the single model
        let (with, fw) = match chosen {
            Some(_) => (
                answer.ncols() + s.ncols(),
                fit_added(&answer, shared_answer.as_ref(), &s, &yu, p),
            ),
            None => (single, fs.clone()),
        };
        // the fits and their column counts (the designs dropped: 91 MB each at 200,000 points)
        (fs, single, fw, with)
    });
    for (k, ((id, _), (fs, single, fw, with))) in alts.iter().zip(fitted).enumerate() {
        let shape = k >= candidates.len();
        // the answer's own effect is not an alternative to it
        if !(fw.rank == answer_rank && fs.rank == answer_rank) {
            push(id.clone(), single, fs);
        }
        // a nuisance family is an alternative to the answer, never added to a named one
        if chosen.is_some() && fw.rank > answer_rank && !shape {
            push(format!("answer+{id}"), with, fw);
        }
    }
    // the error motions, pooled into one random effect beside the answer's model, as one more
    // alternative (not with `unexplained`: its residual is the structure's, whitened): what a
    // named effect leaves of an axis's error motion (a pitch error named as its scale) moves the
    // location errors too
    let random = whitener
        .is_none()
        .then(|| {
            pooled_fit(
                answer_factor.as_ref().unwrap_or(&base_factor),
                &yu,
                &pooled,
                used,
                sigma,
            )
        })
        .flatten()
        .map(|mut r| {
            r.beta = r.beta.rows(0, p).into_owned();
            r.extra = r.extra.view((0, 0), (p, p)).into_owned();
            r
        });
    if let Some(r) = &random {
        models.push((POOLED_ID.into(), r.beta.clone(), answer_score + r.score));
    }
    // prior: half the mass on the answer's model (the diagnosis chose it), the other half
    // shared by the alternatives, the nuisance families together counting as one
    let is_shape = |id: &str| nuisance.iter().any(|f| f.id == id);
    let m = models.iter().filter(|x| is_shape(&x.0)).count();
    for x in models.iter_mut().filter(|x| is_shape(&x.0)) {
        x.2 += 2.0 * (m as f64).ln();
    }
    let k = (models.len() - 1 - m + usize::from(m > 0)).max(1) as f64;
    models[0].2 -= 2.0 * k.ln();
    let best = models.iter().map(|m| m.2).fold(f64::INFINITY, f64::min);
    let raw: Vec<f64> = models.iter().map(|m| (-0.5 * (m.2 - best)).exp()).collect();
    let total: f64 = raw.iter().sum();
    let mut out = ModelSpread {
        covariance: vec![vec![0.0; p]; p],
        ..ModelSpread::default()
    };
    for ((_, b, _), w) in models.iter().zip(&raw) {
        let d = b - &b0;
        for i in 0..p {
            for j in 0..p {
                out.covariance[i][j] += w / total * d[i] * d[j];
            }
        }
    }
    // the pooled model's own covariance beyond the answer's model's, at its weight
    if let Some(r) = &random {
        let w = models
            .iter()
            .zip(&raw)
            .find(|(x, _)| x.0 == POOLED_ID)
            .map_or(0.0, |(_, w)| w / total);
        for (i, row) in out.covariance.iter_mut().enumerate() {
            for (j, c) in row.iter_mut().enumerate() {
                *c += w * r.extra[(i, j)];
            }
        }
    }
    for (j, name) in names.iter().enumerate().take(p) {
        out.std.insert(name.clone(), out.covariance[j][j].sqrt());
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
    use crate::assert_near;
    use crate::effects::data::NamedColumns;
    use crate::numerics::random::Sampler;
    use crate::parameter::{Effect, ParamId};

    /// A line `[1, t]` on `n` points of `[0, 1)` as the location errors' columns, and a shape
    /// they partly absorb: half a constant plus a bump the line cannot follow.
    fn line_and_bump(n: usize) -> (DMatrix<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..n).map(|i| i as f64 / n as f64).collect();
        let a = DMatrix::from_fn(n, 2, |i, j| if j == 0 { 1.0 } else { t[i] });
        let e = t
            .iter()
            .map(|x| 0.5 + (-(x - 0.5f64).powi(2) / 0.005).exp())
            .collect();
        (a, e)
    }

    /// An effect the baseline cannot see apart from a location error moves that error; the
    /// model it is fitted in has the weight, and the spread is the move.
    #[test]
    fn a_hidden_effect_widens_what_it_moves() {
        let n = 60;
        let (a, e) = line_and_bump(n);
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
            .unwrap()
            .into(),
            family: None,
        };
        let s = model_spread(
            &a,
            &["c".into(), "m".into()],
            &y,
            &used,
            std::slice::from_ref(&c),
            &[],
            Answer::default(),
            0.01,
            Threads::ONE,
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
            &[],
            Answer {
                chosen: Some(&c.signature.matrix),
                whitener: None,
            },
            0.01,
            Threads::ONE,
        );
        assert!(s.std["c"] < 0.01, "{:?}", s.std);
    }

    /// A shape no candidate names (a [`Nuisance`] family) moves the location errors as a hidden
    /// candidate does: the family's model takes the weight and the spread is the move (the
    /// intercept's, about 0.1 + 0.2·0.125 as in the test above). On noise alone its weight is
    /// below its prior (½ here, the one alternative; about 1/40 among a machine's candidates)
    /// and the spread is of the order of the intercept's own std, not of the shape's move
    /// (measured: weight 0.33, spread 1.10 std, against 0.1 / 0.00255 = 39 std with the shape).
    #[test]
    fn a_shape_no_candidate_names_widens_what_it_moves() {
        let n = 60;
        let (a, e) = line_and_bump(n);
        let shape = Nuisance {
            id: "probing".into(),
            pooled: false,
            columns: DMatrix::from_column_slice(n, 1, &e),
        };
        let mut rng = Sampler::new(1);
        let noise: Vec<f64> = (0..n).map(|_| 0.01 * rng.normal()).collect();
        let used: Vec<usize> = (0..n).collect();
        let names = ["c".to_string(), "m".to_string()];
        let spread = |y: &[f64]| {
            model_spread(
                &a,
                &names,
                y,
                &used,
                &[],
                std::slice::from_ref(&shape),
                Answer::default(),
                0.01,
                Threads::ONE,
            )
        };
        let y: Vec<f64> = e.iter().zip(&noise).map(|(v, z)| 0.2 * v + z).collect();
        let s = spread(&y);
        assert!(s.weights["probing"] > 0.99, "{:?}", s.weights);
        assert!(s.std["c"] > 0.09, "{:?}", s.std);
        let s = spread(&noise);
        let own = 0.01 * Factor::new(&a, None).cov[(0, 0)].sqrt();
        assert!(s.weights["probing"] < 0.5, "{:?}", s.weights);
        assert!(s.std["c"] < 1.5 * own, "{:?} against {own}", s);
    }

    /// A named effect that is half the part's (a tool's wear with a run-in: a wear and a radius
    /// change) leaves the other half to bias the location errors; the model of the two together
    /// holds the weight, and the spread is the bias.
    #[test]
    fn the_answer_with_a_second_effect_shows_its_bias() {
        let n = 80;
        let t: Vec<f64> = (0..n).map(|i| i as f64 / n as f64).collect();
        let a = DMatrix::from_fn(n, 1, |i, _| t[i]);
        let radius = vec![-1.0; n];
        let wear: Vec<f64> = t.iter().map(|x| x * x).collect();
        let mut rng = Sampler::new(2);
        let y: Vec<f64> = (0..n)
            .map(|i| 0.3 * t[i] + 0.05 * radius[i] + 0.1 * wear[i] + 0.002 * rng.normal())
            .collect();
        let candidate = |effect: Effect, col: &[f64]| Candidate {
            effect,
            signature: NamedColumns::try_new(
                vec![ParamId::Effect { effect, index: 0 }],
                DMatrix::from_column_slice(n, 1, col),
            )
            .unwrap()
            .into(),
            family: None,
        };
        let c = [
            candidate(Effect::ToolRadius, &radius),
            candidate(Effect::ToolWear, &wear),
        ];
        let used: Vec<usize> = (0..n).collect();
        let chosen = DMatrix::from_column_slice(n, 1, &wear);
        let s = model_spread(
            &a,
            &["m".into()],
            &y,
            &used,
            &c,
            &[],
            Answer {
                chosen: Some(&chosen),
                whitener: None,
            },
            0.002,
            Threads::ONE,
        );
        assert!(s.weights["answer+tool_radius"] > 0.99, "{:?}", s.weights);
        // the answer's slope with the wear alone, against the pair's (≈ the true 0.3)
        let x = hstack(&a, &chosen);
        let b0 = fit(x.clone(), &DVector::from_column_slice(&y), 1).beta;
        let full = hstack(&x, &DMatrix::from_column_slice(n, 1, &radius));
        let b1 = fit(full, &DVector::from_column_slice(&y), 1).beta;
        assert!((b1[0] - 0.3).abs() < 0.01, "{b1}");
        assert_near!(
            s.std["m"],
            (b1[0] - b0[0]).abs(),
            0.01 * (b1[0] - b0[0]).abs()
        );
        assert_near!(s.covariance[0][0], s.std["m"].powi(2), 1e-15);
    }
}
