//! WHICH effect: each candidate added to the baseline on its own and refitted, in-sample and on
//! withheld points.
//!
//! Fit (Frisch–Waugh–Lovell): with `P` the projector on the baseline's column space,
//! `r₀ = (I − P) y` the baseline residual and `U = (I − P) S` the part of the candidate's signature
//! the baseline cannot absorb, the candidate's parameters are `θ = U⁺ r₀` and the joint residual is
//! `r₁ = r₀ − U θ`, identical to refitting baseline and candidate together. `q` = rank of `U`
//! (the parameters that add something the baseline does not already have).
//!
//! Criteria, and why:
//! - **F-test** `F = ((RSS₀ − RSS₁)/q) / (RSS₁/(n − p − q))` against `F(q, n − p − q)`: the
//!   classical test for nested linear models, valid whatever σ is; **Bonferroni**: the p-value is
//!   multiplied by the number K of candidates tried, so that trying every candidate keeps the
//!   family-wise false-alarm rate at α.
//! - **BIC** `n ln(RSS/n) + k ln n` (k = parameters): a penalty of `ln n` per extra parameter.
//! - **Ranking** on withheld points: the cross-validated mean square `cv_mse` (folds of
//!   [`crate::gap::folds`]) penalised like BIC, `cv_score = n ln(cv_mse) + q ln n`: a candidate with
//!   more parameters must predict unseen points better by a factor `n^{1/n}` per parameter
//!   (≈ 4.7 % in mean square for 100 points), so a nested candidate (`tool_taper` ⊃
//!   `tool_radius`) only wins when its extra parameter is real.

use crate::numerics::parallel::{map, map_mut, Threads};
use std::collections::BTreeMap;

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::effects::data::{Candidate, PointMeta};
use crate::gap::folds::FoldFactor;
use crate::gap::shape::{fit_shape, scan_family, FamilyScan, ShapeFit, Unabsorbed};
use crate::identify::solve::{hstack, max_abs, rms, Factor};
use crate::numerics::stats;
use crate::parameter::{Effect, ParamId};

/// A fitted value with its standard deviation (units of the parameter).
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Estimate {
    pub value: f64,
    pub std: f64,
}

/// Named estimates `value ± √(s²·cov_jj)` of a least-squares fit.
pub fn estimates(
    names: &[String],
    values: &DVector<f64>,
    cov: &DMatrix<f64>,
    s2: f64,
) -> BTreeMap<String, Estimate> {
    // Inserted one by one: `collect` into a map sorts with a copy of the sort code of its own
    // (numerics::order).
    let mut out = BTreeMap::new();
    for (j, name) in names.iter().enumerate() {
        let std = (s2 * cov[(j, j)]).max(0.0).sqrt();
        out.insert(
            name.clone(),
            Estimate {
                value: values[j],
                std,
            },
        );
    }
    out
}

/// Before/after figures on one curve (mm).
#[derive(Debug, Clone, Serialize)]
pub struct CurveShrink {
    pub curve: String,
    pub rms_before: f64,
    pub rms_after: f64,
    pub max_before: f64,
    pub max_after: f64,
    pub cv_rms_before: f64,
    pub cv_rms_after: f64,
}

/// The withheld-point figures of one model.
#[derive(Debug, Clone)]
pub struct CvResult {
    /// Sum of squared withheld errors per point and how many times it was withheld.
    pub ss: Vec<f64>,
    pub count: Vec<usize>,
}

impl CvResult {
    /// No fold yet, for `n` points.
    fn zeros(n: usize) -> Self {
        Self {
            ss: vec![0.0; n],
            count: vec![0; n],
        }
    }

    /// Adds the prediction errors `pred_err` of fold `f`'s withheld points.
    fn add(&mut self, f: &FoldFactor, pred_err: &DVector<f64>) {
        for (k, &i) in f.test.iter().enumerate() {
            self.ss[i] += pred_err[k] * pred_err[k];
            self.count[i] += 1;
        }
    }

    pub fn mse(&self) -> f64 {
        let c: usize = self.count.iter().sum();
        if c == 0 {
            f64::NAN
        } else {
            self.ss.iter().sum::<f64>() / c as f64
        }
    }
    pub fn rms_of(&self, idx: &[usize]) -> f64 {
        let ss: f64 = idx.iter().map(|&i| self.ss[i]).sum();
        let c: usize = idx.iter().map(|&i| self.count[i]).sum();
        if c == 0 {
            f64::NAN
        } else {
            (ss / c as f64).sqrt()
        }
    }
}

/// Cross-validates the baseline plus signature `s` (`n × q`, may have 0 columns).
pub fn cross_validate(folds: &[FoldFactor], s: &DMatrix<f64>, n: usize) -> CvResult {
    let mut cv = CvResult::zeros(n);
    for f in folds {
        let pred_err = if s.ncols() == 0 {
            let beta = f.base.solve_products(&f.qty_train);
            &f.y_test - &f.a_test * beta
        } else {
            let s_train = s.select_rows(&f.train);
            let (u, qts) = f.base.unabsorbed_with_products(&s_train);
            fold_error(f, s, &s_train, u, &qts)
        };
        cv.add(f, &pred_err);
    }
    cv
}

/// [`cross_validate`] of each of `ss` (each with columns), a fold at a time: the training rows
/// of every signature off the fold's baseline together ([`Factor::unabsorbed_each`]: the fold's
/// basis read twice a thread instead of twice a candidate, issue 31), then each candidate's
/// prediction. With fewer candidates than folds (a scan's few, its dozen folds) the folds are
/// shared out between `threads` threads, each fold's work on one (shared within a fold, two or
/// three candidates had left a thread idle most of the folds' time: ~40 ms of a 20,000-point
/// scan's 0.75 s in a profile, issue 31); else each fold's candidates are. The errors are added
/// in the folds' order either way: the same numbers as [`cross_validate`] of each.
pub fn cross_validate_each(
    folds: &[FoldFactor],
    ss: &[&DMatrix<f64>],
    n: usize,
    threads: Threads,
) -> Vec<CvResult> {
    let mut cvs: Vec<CvResult> = ss.iter().map(|_| CvResult::zeros(n)).collect();
    let by_fold = ss.len() < folds.len();
    let (outer, inner) = if by_fold {
        (threads, Threads::ONE)
    } else {
        (Threads::ONE, threads)
    };
    // (a fold at a time on each thread: its signatures' training rows are held for it alone)
    let errors = map(outer, folds, |f| fold_errors(f, ss, inner));
    for (f, errors) in folds.iter().zip(&errors) {
        for (cv, e) in cvs.iter_mut().zip(errors) {
            cv.add(f, e);
        }
    }
    cvs
}

/// The prediction error of each of `ss` on fold `f`'s withheld points ([`fold_error`]), the
/// candidates on `threads` threads.
fn fold_errors(f: &FoldFactor, ss: &[&DMatrix<f64>], threads: Threads) -> Vec<DVector<f64>> {
    let trains: Vec<DMatrix<f64>> = map(threads, ss, |s| s.select_rows(&f.train));
    let refs: Vec<&DMatrix<f64>> = trains.iter().collect();
    let us = f.base.unabsorbed_each_with_products(&refs, threads);
    // each signature, its training rows, and their part outside the baseline and products
    // with its basis
    let mut items: Vec<(&DMatrix<f64>, &DMatrix<f64>, OffBasis)> = ss
        .iter()
        .zip(&trains)
        .zip(us)
        .map(|((&s, t), u)| (s, t, u))
        .collect();
    map_mut(threads, &mut items, |(s, t, (u, qts))| {
        fold_error(f, s, t, std::mem::replace(u, DMatrix::zeros(0, 0)), qts)
    })
}

/// A matrix's part outside a basis and its products with the basis
/// ([`Factor::unabsorbed_with_products`]).
type OffBasis = (DMatrix<f64>, DMatrix<f64>);

/// The prediction error on fold `f`'s withheld points of the baseline plus `s` (with columns)
/// fitted on its training points (`s_train`, `u` its part outside the fold's baseline and `qts`
/// its products `Qᵀs_train` with the baseline's basis).
#[cfg_attr(target_arch = "wasm32", target_feature(enable = "simd128"))]
fn fold_error(
    f: &FoldFactor,
    s: &DMatrix<f64>,
    s_train: &DMatrix<f64>,
    u: DMatrix<f64>,
    qts: &DMatrix<f64>,
) -> DVector<f64> {
    let scale: Vec<f64> = (0..s.ncols()).map(|j| s_train.column(j).norm()).collect();
    let fu = Factor::of(u, Some(&scale));
    let theta = fu.solve(&f.r0_train);
    // the baseline's solution for y − Sθ from `Qᵀ(y − Sθ) = Qᵀy − (QᵀS)θ`: the fold's basis
    // (n × r, 14 MB at 200,000 points) not read again, where it had been read once a candidate
    // a fold (nalgebra's `Qᵀx`, 0.5 s of a 200,000-point scan's 1.2 s of CPU in the folds)
    let beta = f.base.solve_products(&(&f.qty_train - qts * &theta));
    let s_test = s.select_rows(&f.test);
    &f.y_test - &f.a_test * beta - s_test * theta
}

/// Evidence for one candidate.
#[derive(Debug, Clone, Serialize)]
pub struct Evidence {
    /// Parameters that add a direction the baseline does not have (rank of `(I − P) S`).
    pub added_rank: usize,
    pub f: f64,
    pub p_value: f64,
    /// `min(1, p · K)`.
    pub p_bonferroni: f64,
    pub significant: bool,
    pub delta_bic: f64,
    /// `cv_score − cv_score(baseline)`; negative = better on withheld points.
    pub delta_cv_score: f64,
    /// RMS over the points of the part of the fitted effect the baseline cannot absorb (mm).
    pub unabsorbed_rms: f64,
    /// RMS of the fitted effect itself (mm).
    pub effect_rms: f64,
    /// `‖P·effect‖ / ‖effect‖`: how much of the fitted effect the baseline can mimic.
    pub absorbed_fraction: f64,
    /// Per parameter, `‖P·column‖ / ‖column‖`.
    pub absorbed_fraction_per_parameter: BTreeMap<String, f64>,
    /// Per parameter, the magnitude whose unabsorbed part has an RMS of 2.5 σ (param units).
    pub detection_limit: BTreeMap<String, f64>,
    /// `unabsorbed_rms > 2.5 σ`.
    pub above_limit: bool,
    /// σ of the rule (mm): the given repeatability, else `√(RSS₁/(n − p − q))`.
    pub sigma: f64,
    /// σ independent of smooth structure with this candidate in the model (mm).
    pub sigma_smooth: f64,
    /// Residual structure left after adding the candidate: `√max(0, RSS₁/(n−p−q) − σ_smooth²)` (mm).
    pub structure_after: f64,
    /// Pooled runs-test p-value of the residual after the candidate.
    pub runs_p_after: f64,
    /// Pooled lag-1 autocorrelation of the residual after the candidate.
    pub lag1_after: f64,
}

/// One candidate, fitted.
#[derive(Debug, Clone, Serialize)]
pub struct CandidateFit {
    pub effect: Effect,
    /// The second effect when this is the joint fit of a pair ([`crate::gap::pairs`]); its
    /// parameters are then named `<effect>.<parameter>`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub with: Option<Effect>,
    /// The fitted shape of a family (its lag, its warm-up), with its interval.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shape: Option<ShapeFit>,
    pub parameters: BTreeMap<String, Estimate>,
    /// In-sample residual RMS after adding the candidate (mm).
    pub rms: f64,
    pub max_abs: f64,
    /// RMS on withheld points (mm).
    pub cv_rms: f64,
    /// `1 − rms / rms_before`.
    pub shrink: f64,
    /// `1 − cv_rms / cv_rms_before`.
    pub cv_shrink: f64,
    pub evidence: Evidence,
    pub per_curve: Vec<CurveShrink>,
    /// `cv_score = n ln(cv_mse) + q ln n` (for ranking).
    #[serde(skip)]
    pub cv_score: f64,
    /// Unabsorbed part of the fitted effect (for equivalence with other candidates), one value a
    /// point; the diagnosis's working span, emptied once its report is made
    /// ([`CandidateFit::release_spans`]).
    #[serde(skip)]
    pub unabsorbed_effect: DVector<f64>,
    /// Orthonormal basis of the unabsorbed span `(I − P) S` (a row a point); emptied with
    /// `unabsorbed_effect`.
    #[serde(skip)]
    pub unabsorbed_basis: DMatrix<f64>,
}

impl CandidateFit {
    /// Empties the unabsorbed effect and span, which the diagnosis reads (the pairs, the
    /// equivalences, the verdict) and its report does not: at 200,000 points a fit's are 3-10 MB,
    /// and a backlash's take-up round diagnoses the part again while the round before is held.
    pub fn release_spans(&mut self) {
        self.unabsorbed_effect = DVector::zeros(0);
        self.unabsorbed_basis = DMatrix::zeros(0, 0);
    }
}

/// The baseline fit shared by every candidate.
#[derive(Debug, Clone)]
pub struct BaselineFit {
    pub factor: Factor,
    pub residual: DVector<f64>,
    pub cv: CvResult,
    pub cv_score: f64,
    pub rss: f64,
}

pub use crate::measurement::smooth_noise::SmoothFit;

/// Context shared by the candidate fits.
pub struct Context<'a> {
    pub y: &'a DVector<f64>,
    pub a: &'a DMatrix<f64>,
    pub points: &'a [PointMeta],
    /// The points' curves (their indices in increasing `u`, [`crate::effects::data::curve_sequences`]), found once.
    pub sequences: &'a [(String, Vec<usize>)],
    pub baseline: &'a BaselineFit,
    pub folds: &'a [FoldFactor],
    /// CMM repeatability when given (mm).
    pub given_sigma: Option<f64>,
    /// The baseline augmented with the per-curve smooth basis of [`crate::measurement::smooth_noise`].
    pub smooth: &'a SmoothFit,
    /// The Bonferroni factor: the candidates tried, a family counted by its effectively
    /// independent shapes ([`crate::gap::shape::scan_family`]).
    pub tries: f64,
    pub alpha: f64,
    pub detect_factor: f64,
    /// The `servo_common` column's part outside the baseline when the part has the column
    /// (projected once a diagnosis): a servo lag's parameter is estimated with it (the
    /// candidate fit).
    pub servo_common: Option<&'a Unabsorbed>,
    /// Threads a family's members are searched on ([`crate::gap::pairs`]: the same numbers).
    pub threads: Threads,
}

/// `cv_score` of a model with `q` parameters beyond the baseline.
pub fn cv_score(mse: f64, q: usize, n: usize) -> f64 {
    let nf = n as f64;
    nf * mse.max(f64::MIN_POSITIVE).ln() + q as f64 * nf.ln()
}

/// Per-curve before/after figures.
pub fn per_curve(
    sequences: &[(String, Vec<usize>)],
    before: &[f64],
    after: &[f64],
    cv_before: &CvResult,
    cv_after: &CvResult,
) -> Vec<CurveShrink> {
    sequences
        .iter()
        .map(|(curve, idx)| {
            let b: Vec<f64> = idx.iter().map(|&i| before[i]).collect();
            let a: Vec<f64> = idx.iter().map(|&i| after[i]).collect();
            CurveShrink {
                curve: curve.clone(),
                rms_before: rms(&b),
                rms_after: rms(&a),
                max_before: max_abs(&b),
                max_after: max_abs(&a),
                cv_rms_before: cv_before.rms_of(idx),
                cv_rms_after: cv_after.rms_of(idx),
            }
        })
        .collect()
}

/// A servo lag's parameter with the common rounding (`servo_common`): an axis trailing the
/// others by `l` lags behind its command with every other axis, by `L = F/Kv`, and that lag
/// rounds the path by `(L²/2)·d²q/ds²` (effects.md, "Servo rounding"). The rounding is below
/// the detection limit on most parts, yet its unabsorbed part is correlated with a lag's (0.70
/// for Y on the built-in part), so a lag fitted alone takes it up: 14-25 % on Y with `L`
/// 0.56-1.09 mm, 1 % once fitted together (`effects_families_physics`, servos integrated in
/// time). Only the estimate: the test and the ranking stay those of the lag alone (the rounding
/// is a nuisance of the estimate, not a second effect to detect). `None` for a candidate without
/// a lag, a part without the rounding's column, or a pair that holds it (the rank does not grow).
/// `q`: the rank the lag's columns add; `u`, `scale`: their part outside the baseline and their
/// norms, from the lag's own fit (the unabsorbed part is taken column by column, so these are
/// the numbers of the pair's projection).
#[inline(never)]
fn with_rounding(
    ctx: &Context,
    c: &Candidate,
    q: usize,
    keys: &[String],
    (u, scale): (&DMatrix<f64>, &[f64]),
) -> Option<BTreeMap<String, Estimate>> {
    let common = ctx.servo_common?;
    let lagged = c
        .signature
        .params
        .iter()
        .any(|id| matches!(id.effect(), Some(Effect::ServoLag(_))));
    if !lagged {
        return None;
    }
    let u = hstack(u, &common.u);
    let scale: Vec<f64> = scale.iter().chain(&common.norms).copied().collect();
    let fu = Factor::new(&u, Some(&scale));
    let theta = fu.solve(&ctx.baseline.residual);
    if fu.rank != q + 1 {
        return None;
    }
    let r0 = &ctx.baseline.residual;
    let rss = (r0 - u * &theta).norm_squared();
    let dof = (r0.len().saturating_sub(ctx.baseline.factor.rank + fu.rank)).max(1) as f64;
    Some(estimates(keys, &theta, &fu.cov, rss / dof))
}

/// The columns `s` on the baseline (Frisch–Waugh–Lovell): their unabsorbed part `U`, their norms
/// (what its rank is judged against), its factor and `θ = U⁺r₀`.
#[inline(never)]
fn fwl_fit(ctx: &Context, s: &DMatrix<f64>) -> (DMatrix<f64>, Vec<f64>, Factor, DVector<f64>) {
    let scale: Vec<f64> = (0..s.ncols()).map(|j| s.column(j).norm()).collect();
    let u = ctx.baseline.factor.unabsorbed(s);
    let fu = Factor::new(&u, Some(&scale));
    let theta = fu.solve(&ctx.baseline.residual);
    (u, scale, fu, theta)
}

/// The names a candidate's fit reports its parameters by: the effect's own parameter names
/// (`dR0`, `g`) for one effect, `<effect>.<parameter>` for a pair of effects ([`super::pairs`]).
fn parameter_keys(c: &Candidate) -> Vec<String> {
    let ids = &c.signature.params;
    let one_effect = ids.iter().all(|id| id.effect() == Some(c.effect));
    ids.iter()
        .map(|id| match id {
            ParamId::Effect { effect, index } if one_effect => {
                effect.parameters()[*index].0.to_string()
            }
            _ => id.name(),
        })
        .collect()
}

/// The candidates at the shapes the diagnosis fitted (a family's lag or warm-up; the others as
/// they are), each of one shape: what the final fit uses. The members of a pair verdict at the
/// shapes fitted jointly ([`crate::gap::pairs::PairFit::shapes`]), every other candidate at its
/// single fit's.
pub fn at_fitted_shapes(
    candidates: &[Candidate],
    fits: &[CandidateFit],
    pair: Option<&crate::gap::pairs::PairFit>,
) -> Vec<Candidate> {
    candidates
        .iter()
        .map(|c| {
            let joint = pair.and_then(|p| {
                if p.first == c.effect {
                    Some(p.shapes[0])
                } else if p.second == c.effect {
                    Some(p.shapes[1])
                } else {
                    None
                }
            });
            let index = joint.unwrap_or_else(|| {
                fits.iter()
                    .find(|f| f.effect == c.effect && f.with.is_none())
                    .and_then(|f| f.shape.as_ref())
                    .map(|s| s.grid_index)
            });
            c.at_shape(index)
        })
        .collect()
}

/// Fits one candidate on top of the baseline; a family at the shape that fits best
/// ([`crate::gap::shape`]).
pub fn fit_candidate(ctx: &Context, c: &Candidate) -> CandidateFit {
    let scan = scan_family(&ctx.baseline.factor, Some(&ctx.baseline.residual), c);
    fit_searched(ctx, c, scan)
}

/// [`fit_candidate`] with the family already scanned on the baseline and its residual
/// ([`scan_family`]: its effectively independent shapes, counted, and each member's fit).
pub fn fit_searched(ctx: &Context, c: &Candidate, scan: FamilyScan) -> CandidateFit {
    let (at, shape) = searched_shape(ctx, c, scan);
    let mut fit = fit_one_shape(ctx, &at, Projected::default());
    fit.shape = shape;
    fit
}

/// From this many points on, [`fit_all_searched`] projects the candidates' columns off the
/// smooth fit's basis and each fold's baseline together ([`Factor::unabsorbed_each`]); below,
/// a candidate at a time (the same numbers).
pub const TOGETHER_ROWS: usize = 2000;

/// The most entries (rows × columns) of the signatures [`fit_all_searched`] projects together:
/// the candidates are taken in runs of at most this many (a candidate of more alone), so what a
/// run holds at once (its signatures, their parts off the smooth basis, each one's withheld
/// errors, a fold's training rows and their parts off its baseline: about six copies) stays
/// bounded whatever the points: every candidate of a 20,000-point scan in one run (26 columns),
/// six columns a run at 200,000 points (a run of every candidate had been 70 MB more at the
/// peak there, issue 31).
pub const TOGETHER_ENTRIES: usize = 1_200_000;

/// [`fit_searched`] of each candidate with its scan, side by side on `threads` threads: the
/// same fits. On a dense scan (more than [`TOGETHER_ROWS`] points) the signatures at their
/// fitted shapes are projected off the smooth fit's basis (for σ under the smooth basis) and
/// off each fold's baseline (cross-validation) together, in runs of [`TOGETHER_ENTRIES`]
/// entries: each basis read twice a thread and a run instead of twice a candidate (at 200,000
/// points the smooth fit's is 90 MB, its reads and the folds' a tenth of the diagnosis's CPU,
/// issue 31). The page's wasm fits a candidate at a time (the same numbers).
pub fn fit_all_searched(
    ctx: &Context,
    searched: &[(&Candidate, FamilyScan)],
    threads: Threads,
) -> Vec<CandidateFit> {
    let n = ctx.y.len();
    // (the page's wasm, on one thread, takes a candidate at a time: the same numbers, and the
    // batches' code kept out of its module, which is at its size cap)
    if n <= TOGETHER_ROWS || cfg!(target_arch = "wasm32") {
        return map(threads, searched, |(c, scan)| {
            fit_searched(ctx, c, scan.clone())
        });
    }
    let mut fits = Vec::with_capacity(searched.len());
    let mut start = 0;
    while start < searched.len() {
        // the next run: candidates while their columns stay within the bound (one at least)
        let mut end = start + 1;
        let mut width = searched[start].0.signature.ncols();
        while end < searched.len()
            && (width + searched[end].0.signature.ncols()) * n <= TOGETHER_ENTRIES
        {
            width += searched[end].0.signature.ncols();
            end += 1;
        }
        fits.extend(fit_run(ctx, &searched[start..end], threads));
        start = end;
    }
    fits
}

/// [`fit_all_searched`]'s fits of one run of candidates, their columns projected together.
fn fit_run(
    ctx: &Context,
    searched: &[(&Candidate, FamilyScan)],
    threads: Threads,
) -> Vec<CandidateFit> {
    let n = ctx.y.len();
    let shaped: Vec<(Candidate, Option<ShapeFit>)> = map(threads, searched, |(c, scan)| {
        searched_shape(ctx, c, scan.clone())
    });
    let mut pre: Vec<Projected> = shaped.iter().map(|_| Projected::default()).collect();
    // (a candidate of no column takes its own path: none is projected)
    let with: Vec<usize> = (0..shaped.len())
        .filter(|&i| shaped[i].0.signature.ncols() > 0)
        .collect();
    let cols: Vec<&DMatrix<f64>> = with
        .iter()
        .map(|&i| &shaped[i].0.signature.matrix)
        .collect();
    if ctx.given_sigma.is_none() {
        let us = ctx.smooth.factor.unabsorbed_each(&cols, threads);
        for (&i, u) in with.iter().zip(us) {
            pre[i].smooth = Some(u);
        }
    }
    let cvs = cross_validate_each(ctx.folds, &cols, n, threads);
    for (&i, cv) in with.iter().zip(cvs) {
        pre[i].cv = Some(cv);
    }
    let mut items: Vec<(Candidate, Option<ShapeFit>, Projected)> = shaped
        .into_iter()
        .zip(pre)
        .map(|((c, shape), p)| (c, shape, p))
        .collect();
    map_mut(threads, &mut items, |(at, shape, pre)| {
        let mut fit = fit_one_shape(ctx, at, std::mem::take(pre));
        fit.shape = shape.take();
        fit
    })
}

/// The candidate at the shape of its family that fits best (itself for a candidate of one
/// shape), and that shape's fit.
fn searched_shape(ctx: &Context, c: &Candidate, scan: FamilyScan) -> (Candidate, Option<ShapeFit>) {
    let shape = c.family.as_ref().and_then(|_| {
        fit_shape(
            &ctx.baseline.factor,
            &ctx.baseline.residual,
            c,
            ctx.baseline.factor.rank,
            ctx.given_sigma.map(|s| s * s),
            scan.effective_shapes,
            scan.members,
            ctx.threads,
        )
    });
    let at = c.at_shape(shape.as_ref().map(|f| f.grid_index));
    (at, shape)
}

/// What [`fit_all_searched`] has computed of a candidate's fit beforehand: its signature's
/// part outside the smooth fit, its cross-validation; `None` for what the fit computes itself.
#[derive(Default)]
struct Projected {
    smooth: Option<DMatrix<f64>>,
    cv: Option<CvResult>,
    in_sample: Option<InSample>,
}

/// The in-sample part of a candidate's fit on the baseline (Frisch–Waugh–Lovell, what
/// [`fit_candidate`] begins with): the columns' part outside the baseline `U`, their norms, its
/// factor, `θ = U⁺r₀`, the residual `r₁ = r₀ − Uθ` and its sum of squares. What the pairs'
/// tests (a) and (b) read ([`crate::gap::pairs`]), before the withheld points are fitted.
pub struct InSample {
    u: DMatrix<f64>,
    scale: Vec<f64>,
    factor: Factor,
    theta: DVector<f64>,
    r1: DVector<f64>,
    rss: f64,
}

impl InSample {
    /// Of the columns `s` on the baseline of `ctx`.
    pub fn of(ctx: &Context, s: &DMatrix<f64>) -> Self {
        let (u, scale, factor, theta) = fwl_fit(ctx, s);
        let r1 = &ctx.baseline.residual - &u * &theta;
        let rss = r1.norm_squared();
        Self {
            u,
            scale,
            factor,
            theta,
            r1,
            rss,
        }
    }

    /// The rank the columns add to the baseline (the fit's `evidence.added_rank`).
    pub fn added_rank(&self) -> usize {
        self.factor.rank
    }

    /// The in-sample residual RMS (mm: the fit's `rms`).
    pub fn rms(&self) -> f64 {
        (self.rss / self.r1.len() as f64).sqrt()
    }

    /// σ of the decision rule (mm: the fit's `evidence.sigma`): the given repeatability, else
    /// the fit's own residual standard error.
    pub fn sigma(&self, ctx: &Context) -> f64 {
        ctx.given_sigma.unwrap_or(self.s2(ctx).sqrt())
    }

    /// `RSS₁/(n − p − q)`.
    fn s2(&self, ctx: &Context) -> f64 {
        let n = self.r1.len();
        let dof1 = (n - ctx.baseline.factor.rank - self.factor.rank).max(1) as f64;
        self.rss / dof1
    }
}

/// [`fit_candidate`] of a candidate of one shape whose in-sample fit is made ([`InSample::of`]
/// of its signature): the same fit.
pub fn fit_in_sample(ctx: &Context, c: &Candidate, in_sample: InSample) -> CandidateFit {
    let pre = Projected {
        in_sample: Some(in_sample),
        ..Projected::default()
    };
    fit_one_shape(ctx, &c.at_shape(None), pre)
}

/// [`fit_candidate`] for the signature of `c` as it is, with what `pre` holds computed.
fn fit_one_shape(ctx: &Context, c: &Candidate, pre: Projected) -> CandidateFit {
    let n = ctx.y.len();
    let nf = n as f64;
    let s = &c.signature.matrix;
    let fit = pre.in_sample.unwrap_or_else(|| InSample::of(ctx, s));
    let s2 = fit.s2(ctx);
    // σ for the decision rule: the given repeatability, else this candidate's own residual
    // standard error (the noise if this candidate is the whole story; larger otherwise).
    let sigma = fit.sigma(ctx);
    let InSample {
        u,
        scale,
        factor: fu,
        theta,
        r1,
        rss: rss1,
    } = fit;
    let q = fu.rank;
    let r0 = &ctx.baseline.residual;
    let rss0 = ctx.baseline.rss;
    let dof1 = (n - ctx.baseline.factor.rank - q).max(1) as f64;
    // σ independent of smooth structure under this candidate's hypothesis: residual of
    // [A | smooth basis | S], by FWL on the factor of [A | smooth basis] computed once.
    let sigma_smooth = ctx.given_sigma.unwrap_or_else(|| {
        let us = pre
            .smooth
            .unwrap_or_else(|| ctx.smooth.factor.unabsorbed(s));
        let fs = Factor::new(&us, Some(&scale));
        let th = fs.solve(&ctx.smooth.residual);
        let rss = (&ctx.smooth.residual - us * th).norm_squared();
        (rss / (n - ctx.smooth.factor.rank - fs.rank).max(1) as f64).sqrt()
    });
    let keys = parameter_keys(c);
    let mut parameters = estimates(&keys, &theta, &fu.cov, s2);
    // a servo lag's parameter with the common rounding ([`with_rounding`])
    if let Some(with) = with_rounding(ctx, c, q, &keys, (&u, &scale)) {
        parameters = with;
    }
    // a servo lag's std holds the first-order formula's own uncertainty
    // ([`crate::sensitivity::servo::FIRST_ORDER_REL`])
    for (id, key) in c.signature.params.iter().zip(&keys) {
        if matches!(id.effect(), Some(Effect::ServoLag(_) | Effect::ServoCommon)) {
            if let Some(e) = parameters.get_mut(key) {
                e.std = e
                    .std
                    .hypot(crate::sensitivity::servo::FIRST_ORDER_REL * e.value.abs());
            }
        }
    }
    let (f, p_value) = if q > 0 && rss1 > 0.0 {
        let f = ((rss0 - rss1).max(0.0) / q as f64) / s2;
        (f, stats::f_sf(f, q as f64, dof1))
    } else {
        (0.0, 1.0)
    };
    let p_bonferroni = (p_value * ctx.tries.max(1.0)).min(1.0);
    let effect = s * &theta;
    let unabsorbed_effect = &u * &theta;
    let effect_norm = effect.norm();
    let absorbed_fraction = if effect_norm > 0.0 {
        (effect_norm.powi(2) - unabsorbed_effect.norm_squared())
            .max(0.0)
            .sqrt()
            / effect_norm
    } else {
        0.0
    };
    let mut absorbed_per = BTreeMap::new();
    let mut detection_limit = BTreeMap::new();
    for (j, name) in keys.iter().enumerate() {
        let un = u.column(j).norm();
        let sn = scale[j];
        absorbed_per.insert(
            name.clone(),
            if sn > 0.0 {
                (1.0 - (un / sn).powi(2)).max(0.0).sqrt()
            } else {
                1.0
            },
        );
        let un_rms = un / nf.sqrt();
        detection_limit.insert(
            name.clone(),
            if un_rms > 0.0 {
                ctx.detect_factor * sigma / un_rms
            } else {
                f64::INFINITY
            },
        );
    }
    let unabsorbed_rms = unabsorbed_effect.norm() / nf.sqrt();
    let cv = pre.cv.unwrap_or_else(|| cross_validate(ctx.folds, s, n));
    let cv_mse = cv.mse();
    let score = cv_score(cv_mse, q, n);
    let seqs: Vec<Vec<f64>> = ctx
        .sequences
        .iter()
        .map(|(_, idx)| idx.iter().map(|&i| r1[i]).collect())
        .collect();
    let rnd = crate::measurement::noise::randomness_pooled(&seqs);
    let rms0 = (rss0 / nf).sqrt();
    let rms1 = (rss1 / nf).sqrt();
    let cv0 = ctx.baseline.cv.mse().sqrt();
    let before: Vec<f64> = r0.iter().copied().collect();
    CandidateFit {
        effect: c.effect,
        with: None,
        shape: None,
        parameters,
        rms: rms1,
        max_abs: max_abs(r1.as_slice()),
        cv_rms: cv_mse.sqrt(),
        shrink: if rms0 > 0.0 { 1.0 - rms1 / rms0 } else { 0.0 },
        cv_shrink: if cv0 > 0.0 {
            1.0 - cv_mse.sqrt() / cv0
        } else {
            0.0
        },
        evidence: Evidence {
            added_rank: q,
            f,
            p_value,
            p_bonferroni,
            significant: q > 0 && p_bonferroni < ctx.alpha,
            delta_bic: nf * (rss1.max(f64::MIN_POSITIVE) / rss0.max(f64::MIN_POSITIVE)).ln()
                + q as f64 * nf.ln(),
            delta_cv_score: score - ctx.baseline.cv_score,
            unabsorbed_rms,
            effect_rms: effect_norm / nf.sqrt(),
            absorbed_fraction,
            absorbed_fraction_per_parameter: absorbed_per,
            detection_limit,
            above_limit: unabsorbed_rms > ctx.detect_factor * sigma,
            sigma,
            sigma_smooth,
            structure_after: (s2 - sigma_smooth * sigma_smooth).max(0.0).sqrt(),
            runs_p_after: rnd.runs_p,
            lag1_after: rnd.lag1,
        },
        per_curve: per_curve(ctx.sequences, &before, r1.as_slice(), &ctx.baseline.cv, &cv),
        cv_score: score,
        unabsorbed_effect,
        unabsorbed_basis: fu.basis,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gap::folds::build_folds;
    use crate::part::Surface;

    /// [`cross_validate_each`] is [`cross_validate`] of each signature bit for bit, on 1, 2 and
    /// 3 threads, the candidates shared out within each fold and the folds shared out: 2,400
    /// points of a scan (2 surfaces × 6 lines, height-band and region folds),
    /// a baseline of 5 columns (each fold's basis: the few-column kernel for the candidates of
    /// at most 5 columns) and signatures of 1, 2, 6 and 1 columns (the one of 6 by the blocked
    /// product, as alone) and one-column ones to as many as the folds. Tolerance: none.
    #[test]
    fn cross_validate_each_is_cross_validate_of_each_bit_for_bit() {
        let n = 2400;
        let points: Vec<PointMeta> = (0..n)
            .map(|i| {
                let (surface, line, k) = (i / 1200, (i % 1200) / 200, i % 200);
                let u = k as f64 / 199.0;
                PointMeta {
                    id: i as u32,
                    curve: format!("{}_L{line}", ["A", "B"][surface]),
                    surface: Surface::BOTH[surface],
                    u,
                    h: 2.0 + 4.0 * line as f64,
                    s: 300.0 * (surface as f64 + u),
                    order: i,
                    nz: 0.1,
                }
            })
            .collect();
        let f = |i: usize, j: usize| ((i * 7 + j * 13) % 17) as f64 - 8.0 + (0.01 * i as f64).sin();
        let a = DMatrix::from_fn(n, 5, |i, j| {
            f(i, j) + (j as f64) * points[i].u.powi(j as i32)
        });
        let y = DVector::from_fn(n, |i, _| (0.03 * i as f64).cos() + 0.1 * f(i, 9));
        let folds = build_folds(&points, &a, &y, 12, Threads::ONE);
        assert!(folds.len() >= 4, "{} folds", folds.len());
        // 1, 2, 6 and 1 columns, then one-column ones: as many as the folds
        let widths: Vec<usize> = [1, 2, 6, 1]
            .into_iter()
            .chain(std::iter::repeat(1))
            .take(folds.len().max(4))
            .collect();
        let ss: Vec<DMatrix<f64>> = widths
            .iter()
            .enumerate()
            .map(|(m, &w)| DMatrix::from_fn(n, w, |i, j| f(i + 5 * m, j + 3 * m) * 1e-3))
            .collect();
        let refs: Vec<&DMatrix<f64>> = ss.iter().collect();
        let want: Vec<CvResult> = ss.iter().map(|s| cross_validate(&folds, s, n)).collect();
        // all (as many as the folds: each fold's candidates shared out), then the first two
        // (fewer than the folds: the folds shared out)
        for k in [ss.len(), 2] {
            assert_eq!(k < folds.len(), k == 2, "{} folds", folds.len());
            for t in [1, 2, 3] {
                let got = cross_validate_each(&folds, &refs[..k], n, Threads::new(t));
                assert_eq!(got.len(), k);
                for (g, w) in got.iter().zip(&want) {
                    assert_eq!(g.count, w.count, "{t} threads");
                    for (a, b) in g.ss.iter().zip(&w.ss) {
                        assert_eq!(a.to_bits(), b.to_bits(), "{t} threads");
                    }
                }
            }
        }
    }
}
