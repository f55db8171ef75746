//! The VERDICT, by the decision rule of effects.md.
//!
//! A candidate is **named** when
//! (a) adding it is significant after the multiple-testing correction (F-test, Bonferroni over
//!     the K candidates tried, family-wise α = [`ALPHA`]),
//! (b) the part of its fitted effect that the baseline cannot absorb has an RMS over the points
//!     above 2.5 σ,
//! (c) it predicts withheld points better than the baseline (`cv_score` lower), and
//! (d) it explains the gap: the structure left after it is at most 2.5 σ.
//! Among candidates passing (a)-(c) the lowest `cv_score` wins. If the winner fails (d), the
//! verdict is `unexplained` (it only explains part of a structured residual). With no winner, the
//! verdict is `unexplained` when the baseline residual is structured beyond 2.5 σ, else `none`,
//! and candidates passing (a) but not (b) are listed as possible, below the detection limit.
//!
//! Candidates reported **equivalent** to the winner: those whose unabsorbed span reproduces the
//! winner's visible (unabsorbed) fitted effect with a cosine ≥ [`super::equivalence::EQUIVALENT_COS`]
//! (the part cannot tell them apart at any magnitude), and those whose fit is not significantly
//! worse than the winner's: `(RSS_b − RSS_win) / σ̂²_win < χ²₁(0.95) = 3.84`.

use serde::Serialize;

use super::catalog::{plain_name, NONE, UNEXPLAINED};
use super::equivalence::{cos_to_span, EQUIVALENT_COS};
use super::pairs::PairFit;
use super::which::{CandidateFit, CurveShrink, Estimate};
use std::collections::BTreeMap;

/// Family-wise false-alarm rate of the significance test.
pub const ALPHA: f64 = 0.05;
/// χ²₁ quantile at 0.95: fits closer than this (in σ² units) are not told apart.
pub const CHI2_1_95: f64 = 3.841_459;

/// The verdict of a diagnosis.
#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    /// An effect id of effects.md, `none` or `unexplained`.
    pub effect: String,
    pub plain_name: String,
    /// Candidates this part cannot tell apart from the named one.
    pub equivalent: Vec<String>,
    /// Residual RMS before/after adding the effect, in-sample (mm).
    pub rms_before: f64,
    pub rms_after: f64,
    pub max_before: f64,
    pub max_after: f64,
    /// Same on withheld points (mm).
    pub cv_rms_before: f64,
    pub cv_rms_after: f64,
    /// Smallest RMS of an effect's unabsorbed part that can be named: 2.5 σ (mm).
    pub detection_limit: f64,
    /// The noise σ used (mm).
    pub sigma: f64,
    /// Fitted parameters of the named effect.
    pub parameters: BTreeMap<String, Estimate>,
    /// Significant candidates whose unabsorbed part is below the detection limit.
    pub possible_below_limit: Vec<String>,
    /// The best candidate when the verdict is `unexplained` but one explains part of the gap.
    pub partial: Option<String>,
    /// A second effect found together with the named one ([`super::pairs`]); empty otherwise.
    /// The figures and parameters (`<effect>.<name>`) are then those of the pair.
    pub with: Vec<String>,
    /// Candidates this part cannot tell apart from the second effect of the pair.
    pub with_equivalent: Vec<String>,
    /// Per curve, before/after.
    pub per_curve: Vec<CurveShrink>,
    /// One sentence saying why.
    pub reason: String,
}

/// Inputs of the decision beyond the candidate fits.
pub struct DecisionInput<'a> {
    pub fits: &'a [CandidateFit],
    pub baseline_cv_score: f64,
    pub baseline_structured: bool,
    pub baseline_structure_rms: f64,
    pub sigma: f64,
    pub detect_factor: f64,
    pub rms_before: f64,
    pub max_before: f64,
    pub cv_rms_before: f64,
    pub baseline_per_curve: Vec<CurveShrink>,
}

/// Applies the decision rule.
pub fn decide(d: &DecisionInput) -> Verdict {
    let limit = d.detect_factor * d.sigma;
    let passing: Vec<&CandidateFit> = d
        .fits
        .iter()
        .filter(|f| {
            f.evidence.significant && f.evidence.above_limit && f.cv_score < d.baseline_cv_score
        })
        .collect();
    let winner = passing
        .iter()
        .min_by(|a, b| a.cv_score.total_cmp(&b.cv_score))
        .copied();
    let possible_below_limit: Vec<String> = d
        .fits
        .iter()
        .filter(|f| f.evidence.significant && !f.evidence.above_limit)
        .map(|f| f.effect.clone())
        .collect();
    let base = |effect: &str, reason: String, partial: Option<String>| Verdict {
        effect: effect.into(),
        plain_name: plain_name(effect).into(),
        equivalent: Vec::new(),
        rms_before: d.rms_before,
        rms_after: d.rms_before,
        max_before: d.max_before,
        max_after: d.max_before,
        cv_rms_before: d.cv_rms_before,
        cv_rms_after: d.cv_rms_before,
        detection_limit: limit,
        sigma: d.sigma,
        parameters: BTreeMap::new(),
        possible_below_limit: possible_below_limit.clone(),
        partial,
        with: Vec::new(),
        with_equivalent: Vec::new(),
        per_curve: d.baseline_per_curve.clone(),
        reason,
    };
    let Some(w) = winner else {
        return if d.baseline_structured {
            base(
                UNEXPLAINED,
                format!(
                    "the residual has {:.1} µm RMS of structure beyond noise (> 2.5σ = {:.1} µm) and no candidate explains it",
                    d.baseline_structure_rms * 1e3,
                    limit * 1e3
                ),
                None,
            )
        } else {
            base(
                NONE,
                format!(
                    "no candidate improves the fit beyond noise: nothing above the detection limit of {:.1} µm RMS (2.5σ, σ = {:.2} µm)",
                    limit * 1e3,
                    d.sigma * 1e3
                ),
                None,
            )
        };
    };
    let limit = d.detect_factor * w.evidence.sigma;
    if w.evidence.structure_after > d.detect_factor * w.evidence.sigma_smooth {
        return base(
            UNEXPLAINED,
            format!(
                "`{}` explains part of the gap, but {:.1} µm RMS of structure remains (> 2.5σ = {:.1} µm)",
                w.effect,
                w.evidence.structure_after * 1e3,
                limit * 1e3
            ),
            Some(w.effect.clone()),
        );
    }
    let equivalent = equivalents(d.fits, w);
    Verdict {
        effect: w.effect.clone(),
        plain_name: plain_name(&w.effect).into(),
        equivalent,
        rms_before: d.rms_before,
        rms_after: w.rms,
        max_before: d.max_before,
        max_after: w.max_abs,
        cv_rms_before: d.cv_rms_before,
        cv_rms_after: w.cv_rms,
        detection_limit: limit,
        sigma: w.evidence.sigma,
        parameters: w.parameters.clone(),
        possible_below_limit,
        partial: None,
        with: Vec::new(),
        with_equivalent: Vec::new(),
        per_curve: w.per_curve.clone(),
        reason: format!(
            "significant after Bonferroni over the candidates (p = {:.2e}), its visible part is {:.1} µm RMS (> 2.5σ = {:.1} µm), best on withheld points, and the residual left is noise",
            w.evidence.p_bonferroni,
            w.evidence.unabsorbed_rms * 1e3,
            limit * 1e3
        ),
    }
}

/// Candidates this part cannot tell apart from the winner `w`: those whose unabsorbed span
/// reproduces `w`'s visible effect (cosine ≥ [`EQUIVALENT_COS`]) or whose fit is not
/// significantly worse (χ²₁ rule of the module doc).
pub fn equivalents(fits: &[CandidateFit], w: &CandidateFit) -> Vec<String> {
    // Noise variance for the comparison: the larger of σ² and the winner's mean square.
    let sigma2 = (w.rms * w.rms)
        .max(w.evidence.sigma * w.evidence.sigma)
        .max(f64::MIN_POSITIVE);
    let rss_w = w.rms * w.rms * w.residual.len() as f64;
    fits.iter()
        .filter(|f| f.effect != w.effect && f.evidence.added_rank > 0)
        .filter(|f| {
            let cos = cos_to_span(&w.unabsorbed_effect, &f.unabsorbed_basis);
            let rss_f = f.rms * f.rms * f.residual.len() as f64;
            cos >= EQUIVALENT_COS || (rss_f - rss_w) / sigma2 < CHI2_1_95
        })
        .map(|f| f.effect.clone())
        .collect()
}

/// The verdict of an accepted pair ([`super::pairs`]): the best single candidate `w` named, the
/// pair's second effect under `with`, the pair's figures and parameters.
pub fn pair_verdict(
    before: &Verdict,
    fits: &[CandidateFit],
    w: &CandidateFit,
    pair: &PairFit,
    detect_factor: f64,
) -> Verdict {
    let f = &pair.fit;
    let limit = detect_factor * f.evidence.sigma;
    Verdict {
        effect: w.effect.clone(),
        plain_name: plain_name(&w.effect).into(),
        equivalent: pair_equivalent(fits, w, &pair.first_equivalent, &pair.second),
        rms_before: before.rms_before,
        rms_after: f.rms,
        max_before: before.max_before,
        max_after: f.max_abs,
        cv_rms_before: before.cv_rms_before,
        cv_rms_after: f.cv_rms,
        detection_limit: limit,
        sigma: f.evidence.sigma,
        parameters: f.parameters.clone(),
        possible_below_limit: before
            .possible_below_limit
            .iter()
            .filter(|c| **c != w.effect && **c != pair.second)
            .cloned()
            .collect(),
        partial: None,
        with: vec![pair.second.clone()],
        with_equivalent: pair_equivalent(
            fits,
            fits.iter().find(|c| c.effect == pair.second).unwrap_or(w),
            &pair.second_equivalent,
            &pair.first,
        ),
        per_curve: f.per_curve.clone(),
        reason: format!(
            "no single candidate explains the gap; `{}` together with `{}` does: `{}` adds {:.1} µm RMS beyond the baseline and `{}` (F-test p = {:.2e}, Bonferroni over the pairs tried), the pair predicts withheld points better than either alone, and the residual left is noise",
            w.effect,
            pair.second,
            pair.second,
            pair.added_rms * 1e3,
            w.effect,
            pair.p_bonferroni,
        ),
    }
}

/// Equivalents of one member `m` of a pair: the swaps that fit as well (`swaps`) and the candidates
/// whose unabsorbed span reproduces `m`'s visible effect; never the pair's `other` member.
fn pair_equivalent(
    fits: &[CandidateFit],
    m: &CandidateFit,
    swaps: &[String],
    other: &str,
) -> Vec<String> {
    let mut out: Vec<String> = swaps.to_vec();
    for f in fits {
        if f.effect != m.effect
            && f.effect != other
            && f.evidence.added_rank > 0
            && !out.contains(&f.effect)
            && cos_to_span(&m.unabsorbed_effect, &f.unabsorbed_basis) >= EQUIVALENT_COS
        {
            out.push(f.effect.clone());
        }
    }
    out
}
