//! The diagnosis: baseline fit → WHERE → WHICH → equivalences → VERDICT → HOW FAR, as one plain
//! function from [`GapInput`] to [`DiagnosisReport`].

use nalgebra::DVector;

use crate::effects::data::curve_sequences;
use crate::effects::data::GapInput;
use crate::effects::GapError;
use crate::gap::equivalence::near_equivalent_pairs_on;
use crate::gap::folds::{build_folds, withheld_sets};
use crate::gap::location::{locate, DETECT_FACTOR};
use crate::gap::pairs::best_pair;
use crate::gap::report::{summary, BaselineReport, DiagnosisReport};
use crate::gap::verdict::{decide, pair_verdict, DecisionInput, Finding, ALPHA};
use crate::gap::which::{
    cross_validate, cv_score, estimates, fit_all_searched, per_curve, BaselineFit, Context,
    SmoothFit,
};
use crate::identify::solve::{max_abs, rms, Factor};
use crate::measurement::layout::curve_degree;
use crate::measurement::noise::NoiseInputs;
use crate::measurement::noise::{
    periodogram_sigma_on, projected_whiteness_on, second_difference_sigma, sinusoid_free_sigma_on,
    SmoothResidual, LJUNG_BOX_LAGS, NOT_WHITE_P,
};
use crate::measurement::ruling_pairs::pair_sigma;
use crate::measurement::smooth_noise::{
    smooth_factor, smooth_sigmas, with_smooth_basis, SMOOTH_DEGREE,
};
use crate::numerics::order::sort_by_key_f64;
use crate::numerics::parallel::Threads;
use crate::parameter::Effect;

/// Options of a diagnosis (defaults: α = 0.05 family-wise, 2.5 σ).
#[derive(Debug, Clone, Copy)]
pub struct DiagnoseOptions {
    /// Family-wise false-alarm rate of the significance tests.
    pub alpha: f64,
    /// `k` of the `k σ` rule: the detection limit of an effect's visible part, the structure
    /// test of WHERE, the "structure left" check of the verdict and of pairs.
    pub detect_factor: f64,
    /// Threads the candidates are scanned and fitted on (the same numbers on any count).
    pub threads: Threads,
}

impl Default for DiagnoseOptions {
    fn default() -> Self {
        Self {
            alpha: ALPHA,
            detect_factor: DETECT_FACTOR,
            threads: Threads::ONE,
        }
    }
}

/// Whether every candidate is judged with the part's σ: with the CMM's floor (the total σ,
/// that floor or with the part's own scatter added). Else each candidate's own residual gives
/// its σ: the right candidate's residual is the most precise estimate of the noise there is.
fn noise_fixed(n: &crate::measurement::noise::NoiseEstimate) -> bool {
    n.given.is_some()
}

/// Diagnoses the sim-to-real gap of one measured part with the default options.
pub fn diagnose(input: &GapInput) -> Result<DiagnosisReport, GapError> {
    diagnose_with(input, DiagnoseOptions::default())
}

/// Diagnoses the sim-to-real gap of one measured part.
pub fn diagnose_with(input: &GapInput, opts: DiagnoseOptions) -> Result<DiagnosisReport, GapError> {
    diagnose_with_smooth(input, opts, None)
}

/// [`diagnose_with`], with the fit of the deviations by `[A | smooth basis]` (the baseline and
/// [`crate::measurement::smooth_noise::smooth_basis`] of degree [`SMOOTH_DEGREE`] of `input`'s points, on every row) when the
/// caller has it ([`crate::measurement::outliers::find_outliers_with_fit`]): the same numbers,
/// not factorised again.
pub fn diagnose_with_smooth(
    input: &GapInput,
    opts: DiagnoseOptions,
    smooth: Option<SmoothFit>,
) -> Result<DiagnosisReport, GapError> {
    let ground = ground(input, opts, smooth)?;
    diagnose_on(input, opts, &ground)
}

/// What a diagnosis computes before its candidates: (a) the baseline fit and its folds, (b)
/// the noise's estimates that WHERE reads. A function of the input's deviations, points, baseline, σ and
/// reversals and of its candidates' widest signature (the folds' rank margin) alone, so a part
/// diagnosed again with the same signatures and other families (a named backlash's take-up,
/// `crate::analysis::diagnosis`) is given the same ground ([`diagnose_on`]) instead of
/// computing it again.
pub struct Ground {
    y: DVector<f64>,
    /// The baseline's parameters and the residual variance they are estimated with.
    beta: DVector<f64>,
    s2: f64,
    baseline: BaselineFit,
    folds: Vec<crate::gap::folds::FoldFactor>,
    sequences: Vec<(String, Vec<usize>)>,
    smooth: SmoothFit,
    /// The noise's estimates from the smooth fit's residual and from the rulings' pairs, for
    /// WHERE ([`locate`]).
    smooth_residual: SmoothResidual,
    pairs: Option<crate::measurement::ruling_pairs::PairSigma>,
}

/// [`Ground`] of `input` (`smooth`: as in [`diagnose_with_smooth`]).
pub fn ground(
    input: &GapInput,
    opts: DiagnoseOptions,
    smooth: Option<SmoothFit>,
) -> Result<Ground, GapError> {
    input.validate()?;
    let n = input.deviations.len();
    let nf = n as f64;
    let y = DVector::from_column_slice(&input.deviations);
    let a = &input.baseline.matrix;

    // (a) baseline fit and residual (a scan's row blocks side by side).
    let factor = Factor::of_on(a.clone(), None, opts.threads);
    let residual = factor.unabsorbed_vec(&y);
    let rss = residual.norm_squared();
    let p = factor.rank;
    let beta = factor.solve(&y);
    let s2 = rss / (n - p).max(1) as f64;
    let max_q = input
        .candidates
        .iter()
        .map(|c| c.signature.ncols())
        .max()
        .unwrap_or(0);
    let folds = build_folds(&input.points, a, &y, a.ncols() + max_q + 2, opts.threads);
    let base_cv = cross_validate(&folds, &nalgebra::DMatrix::zeros(n, 0), n);
    let base_cv_score = cv_score(base_cv.mse(), 0, n);

    // (b) WHERE, noise versus structure.
    // the smooth basis only for its factor (dropped at once: 77 MB at 200,000 points)
    let (sfactor, sresid) = match smooth {
        Some(s) => (s.factor, s.residual),
        None => smooth_factor(
            with_smooth_basis(a, &input.points, SMOOTH_DEGREE, opts.threads),
            &y,
            opts.threads,
        ),
    };
    let (sm, sm_robust, sdof) = smooth_sigmas(&sfactor, &sresid);
    let sequences = curve_sequences(&input.points);
    let curves: Vec<Vec<usize>> = sequences.iter().map(|(_, idx)| idx.clone()).collect();
    let s_path: Vec<f64> = input.points.iter().map(|p| p.s).collect();
    let smooth_seqs: Vec<Vec<f64>> = curves
        .iter()
        .map(|idx| idx.iter().map(|&i| sresid[i]).collect())
        .collect();
    let smooth_at: Vec<(Vec<f64>, Vec<f64>)> = curves
        .iter()
        .zip(&smooth_seqs)
        .map(|(idx, x)| (idx.iter().map(|&i| s_path[i]).collect(), x.clone()))
        .collect();
    let whiteness_p = projected_whiteness_on(
        &curves,
        &sfactor.basis,
        &sresid,
        LJUNG_BOX_LAGS,
        opts.threads,
    )
    .map_or(1.0, |w| w.p_value);
    let smooth_residual = SmoothResidual {
        sigma: sm,
        robust: sm_robust,
        second_difference: second_difference_sigma(&smooth_seqs) * (nf / sdof as f64).sqrt(),
        // the frequencies the curve's smooth basis (degree d: d + 1 columns) removed
        periodogram: periodogram_sigma_on(
            &smooth_at,
            |m| (curve_degree(m, SMOOTH_DEGREE) + 2) / 2,
            opts.threads,
        ),
        // only read when the residual is not white (the frequency search costs a few ms)
        sinusoid_free: (whiteness_p < NOT_WHITE_P)
            .then(|| {
                sinusoid_free_sigma_on(&curves, &s_path, &sfactor.basis, &sresid, opts.threads)
            })
            .flatten(),
        whiteness_p,
        dof: sdof,
    };
    let pairs = pair_sigma(&input.points, residual.as_slice(), &factor.basis);
    let smooth = SmoothFit {
        factor: sfactor,
        residual: sresid,
    };
    let baseline = BaselineFit {
        factor,
        residual,
        cv: base_cv,
        cv_score: base_cv_score,
        rss,
    };
    Ok(Ground {
        y,
        beta,
        s2,
        baseline,
        folds,
        sequences,
        smooth,
        smooth_residual,
        pairs,
    })
}

/// The diagnosis of `input` on its [`Ground`], made by [`ground`] of an input with the same
/// deviations, points, baseline, σ and reversals, and signatures of the same widest width (the
/// folds' margin): the count of the points checked.
pub fn diagnose_on(
    input: &GapInput,
    opts: DiagnoseOptions,
    ground: &Ground,
) -> Result<DiagnosisReport, GapError> {
    input.validate()?;
    let n = input.deviations.len();
    let nf = n as f64;
    if ground.y.len() != n {
        return Err(GapError::LengthMismatch {
            what: "the diagnosis's ground's points".into(),
            got: ground.y.len(),
            expected: n,
        });
    }
    let Ground {
        y,
        beta,
        s2,
        baseline,
        folds,
        sequences,
        smooth,
        smooth_residual,
        pairs,
    } = ground;
    let r0 = baseline.residual.as_slice();
    let a = &input.baseline.matrix;
    let rss = baseline.rss;
    let p = baseline.factor.rank;
    let mut structure = locate(
        r0,
        &input.points,
        p,
        NoiseInputs {
            floor: input.noise_sigma,
            smooth: Some(*smooth_residual),
            pairs: pairs.clone(),
        },
        &input.reversals,
        opts.detect_factor,
    );
    let base_cv_score = baseline.cv_score;
    let sigma = structure.noise.used.max(1e-12);
    // (c) WHICH: each candidate on its own.
    // a family counts as its effectively independent shapes (the search's cost, effects.md)
    // (each family's members fitted on the baseline residual in the same pass)
    // (each family's blocks of members side by side on the threads there are, one family at a
    // time: the families' scans are a third of a dense scan's diagnosis, and a family's kept
    // directions 86 MB at 200,000 points, in one buffer that each family's scan takes in turn)
    let mut directions = Vec::new();
    let scans: Vec<crate::gap::shape::FamilyScan> = input
        .candidates
        .iter()
        .map(|c| {
            crate::gap::shape::scan_family_on(
                &baseline.factor,
                Some(&baseline.residual),
                c,
                opts.threads,
                &mut directions,
            )
        })
        .collect();
    // (86 MB at 200,000 points: not held through the fits below)
    drop(directions);
    let tries: f64 = scans.iter().map(|s| s.effective_shapes).sum();
    // the rounding every lagging axis shares, off the baseline once for every servo lag's fit
    let servo_common = input
        .candidates
        .iter()
        .find(|c| c.effect == Effect::ServoCommon)
        .map(|c| crate::gap::shape::Unabsorbed::of(&baseline.factor, &c.signature.matrix));
    let ctx = Context {
        y,
        a,
        points: &input.points,
        sequences,
        baseline,
        folds,
        // the part's σ for every candidate with a CMM floor; else each candidate's own
        given_sigma: noise_fixed(&structure.noise).then_some(sigma),
        smooth,
        tries,
        alpha: opts.alpha,
        detect_factor: opts.detect_factor,
        servo_common: servo_common.as_ref(),
        threads: opts.threads,
    };
    let searched: Vec<_> = input.candidates.iter().zip(scans).collect();
    let mut fits = fit_all_searched(&ctx, &searched, opts.threads);
    sort_by_key_f64(&mut fits, |f| f.cv_score);
    let spans: Vec<_> = fits
        .iter()
        .filter(|f| f.evidence.added_rank > 0)
        .map(|f| (f.effect, &f.unabsorbed_basis))
        .collect();
    let equivalences = near_equivalent_pairs_on(&spans, opts.threads);
    let invisible = fits
        .iter()
        .filter(|f| f.with.is_none() && f.evidence.added_rank == 0)
        .map(|f| f.effect)
        .collect();
    let layout = crate::measurement::layout::layout(&input.points, invisible);

    // (d) VERDICT and (e) HOW FAR.
    let mut verdict = decide(&DecisionInput {
        fits: &fits,
        baseline_cv_score: base_cv_score,
        baseline_structured: structure.structured,
        baseline_structure_rms: structure.structure_rms,
        implausible_noise: structure
            .noise
            .implausible
            .then_some((structure.noise.estimated, structure.noise.ceiling)),
        sigma,
        detect_factor: opts.detect_factor,
        rms_before: (rss / nf).sqrt(),
        max_before: max_abs(r0),
        cv_rms_before: baseline.cv.mse().sqrt(),
        baseline_per_curve: per_curve(sequences, r0, r0, &baseline.cv, &baseline.cv),
    });
    // (d') a pair, when no single candidate is named.
    // (d'') or a second effect on top of the named one: the single-candidate rule measures the
    // structure left against the smooth-basis σ, which a smooth second effect inflates, so a
    // second effect the named one leaves visible is searched for as the best addition to it.
    let mut pair = None;
    let named_single = match &verdict.finding {
        Finding::Named {
            effect,
            equivalent,
            with: None,
        } => Some((*effect, equivalent.clone())),
        _ => None,
    };
    // on top of a named effect, the pair must keep it (or an equivalent)
    let keeps_named = |pf: &crate::gap::pairs::PairFit| {
        named_single.as_ref().is_none_or(|(named, equivalent)| {
            [pf.first, pf.second]
                .iter()
                .any(|e| e == named || equivalent.contains(e))
        })
    };
    // (the pairs fit a family's shape jointly with the other member)
    // (a pair whose second member is below the limit only when no single candidate is named)
    if let Some(pf) = best_pair(
        &ctx,
        &input.candidates,
        &fits,
        base_cv_score,
        named_single.is_none(),
    )
    .filter(|pf| keeps_named(pf))
    {
        verdict = pair_verdict(&verdict, &fits, &pf, opts.detect_factor);
        pair = Some(pf);
    }
    let backlash_axes: Vec<_> = verdict
        .finding
        .effects()
        .into_iter()
        .filter_map(|e| match e {
            crate::parameter::Effect::Backlash(axis) => Some(axis),
            _ => None,
        })
        .collect();
    structure.mark_verdict_axes(&backlash_axes);
    let mut report = DiagnosisReport {
        baseline: BaselineReport {
            rms: rms(r0),
            max_abs: max_abs(r0),
            cv_rms: baseline.cv.mse().sqrt(),
            parameters: estimates(&input.baseline.names(), beta, &baseline.factor.cov, *s2),
            rank: p,
            condition: baseline.factor.condition,
            points: n,
        },
        where_: structure.entries.clone(),
        structure,
        candidates: fits,
        equivalences,
        folds: withheld_sets(&input.points)
            .into_iter()
            .map(|(name, _)| name)
            .collect(),
        verdict,
        pair,
        layout,
        summary: String::new(),
    };
    report.summary = summary(&report);
    // the fits' spans were the search's (pairs, equivalences, verdict), not the report's
    for f in report.candidates.iter_mut() {
        f.release_spans();
    }
    if let Some(pf) = report.pair.as_mut() {
        pf.fit.release_spans();
    }
    Ok(report)
}
