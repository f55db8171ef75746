//! The VERDICT: the decision rule of effects.md, with two criteria of ours added to it.
//!
//! A candidate is **named** when
//! (a) adding it is significant after the multiple-testing correction (F-test, Bonferroni over
//!     the K candidates tried, family-wise α = [`ALPHA`]) — effects.md;
//! (b) the part of its fitted effect that the baseline cannot absorb has an RMS over the points
//!     above `k σ` (`k` = [`crate::gap::DiagnoseOptions::detect_factor`], 2.5 by default) — effects.md;
//! (c) it predicts withheld points better than the baseline (`cv_score` lower) — **ours**;
//! (d) it explains the gap: the structure left after it is at most `k σ` — **ours**.
//!
//! Why the two additions: (c) a candidate that only fits the points it was fitted on (a column
//! that happens to follow the noise of a few points, or a backlash step that a smooth residual
//! leans on) is significant by (a) yet predicts nothing; requiring a better prediction of
//! withheld curves and regions ([`crate::gap::folds`]) keeps such fits from being named, and ranks the
//! winners. (d) effects.md names the best significant, visible candidate; but when a structured
//! residual is only partly explained, naming its best partial candidate would tell the user the
//! gap is closed when it is not. The verdict is then `unexplained`, with that candidate as
//! `partial`, and a pair of effects is tried ([`crate::gap::pairs`]).
//!
//! Among candidates passing (a)-(c) the lowest `cv_score` wins. If the winner fails (d), the
//! verdict is `unexplained` (it only explains part of a structured residual). With no winner, the
//! verdict is `unexplained` when the baseline residual is structured beyond `k σ`, else `none`
//! (noise), and candidates passing (a) but not (b) are listed as possible, below the detection
//! limit.
//!
//! Candidates reported **equivalent** to the winner: those whose unabsorbed span reproduces the
//! winner's visible (unabsorbed) fitted effect with a cosine ≥ [`crate::gap::equivalence::EQUIVALENT_COS`]
//! (the part cannot tell them apart at any magnitude), and those whose fit is not significantly
//! worse than the winner's: `(RSS_b − RSS_win) / σ̂²_win < χ²₁(0.95) = 3.84`.
//!
//! JSON (shared/spec/cli.md): the verdict is written flat, as scripts read it: `kind`
//! (`noise`, `unexplained`, `named`), `effect` (an id of effects.md, `none` or `unexplained`),
//! `equivalent`, `with` (the pair's second effect, as a list of zero or one id),
//! `with_equivalent`, `partial`, and the figures.

use std::collections::BTreeMap;
use std::fmt;

use serde::{Serialize, Serializer};

use crate::gap::equivalence::{cos_to_span, EQUIVALENT_COS};
use crate::gap::pairs::PairFit;
use crate::gap::which::{CandidateFit, CurveShrink, Estimate};
use crate::numerics::stats::CHI2_1_95;
use crate::parameter::Effect;

/// Family-wise false-alarm rate of the significance test.
pub const ALPHA: f64 = 0.05;

/// What the diagnosis found.
#[derive(Debug, Clone, PartialEq)]
pub enum Finding {
    /// The residual is measurement noise: nothing above the detection limit.
    Noise,
    /// Structure beyond noise that no candidate (nor pair) explains; `partial` is the best
    /// candidate when it explains part of it.
    Unexplained { partial: Option<Effect> },
    /// An effect explains the gap; `with` is the second effect when only a pair does.
    Named {
        effect: Effect,
        /// Candidates this part cannot tell apart from `effect`.
        equivalent: Vec<Effect>,
        with: Option<Member>,
    },
}

/// The second effect of a named pair.
#[derive(Debug, Clone, PartialEq)]
pub struct Member {
    pub effect: Effect,
    /// Candidates this part cannot tell apart from it (in the pair).
    pub equivalent: Vec<Effect>,
}

/// The verdict as one word: what `verdict.effect` holds in the JSON.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum VerdictId {
    /// `none`.
    Noise,
    /// `unexplained`.
    Unexplained,
    /// An effect id of effects.md.
    Effect(Effect),
}

impl VerdictId {
    /// `none`, `unexplained` or the effect's id.
    pub fn as_str(self) -> &'static str {
        match self {
            VerdictId::Noise => "none",
            VerdictId::Unexplained => "unexplained",
            VerdictId::Effect(e) => e.id(),
        }
    }
    /// A plain-language name.
    pub fn plain_name(self) -> &'static str {
        match self {
            // the verdict's rule is the detection limit: structure below it may still be more
            // than noise alone (the summary's `Where:` line says so when the χ² test rejects it)
            VerdictId::Noise => "no unmodelled effect above the detection limit",
            VerdictId::Unexplained => "unexplained structured residual",
            VerdictId::Effect(e) => e.plain_name(),
        }
    }
}

impl fmt::Display for VerdictId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.as_str())
    }
}

impl Serialize for VerdictId {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

impl Finding {
    /// The verdict in one word.
    pub fn id(&self) -> VerdictId {
        match self {
            Finding::Noise => VerdictId::Noise,
            Finding::Unexplained { .. } => VerdictId::Unexplained,
            Finding::Named { effect, .. } => VerdictId::Effect(*effect),
        }
    }
    /// The named effects: none, one, or the two of a pair.
    pub fn effects(&self) -> Vec<Effect> {
        match self {
            Finding::Named { effect, with, .. } => std::iter::once(*effect)
                .chain(with.as_ref().map(|m| m.effect))
                .collect(),
            _ => Vec::new(),
        }
    }
    /// The named effect's equivalents (empty unless named).
    pub fn equivalent(&self) -> &[Effect] {
        match self {
            Finding::Named { equivalent, .. } => equivalent,
            _ => &[],
        }
    }
    /// The second effect of a named pair.
    pub fn with(&self) -> Option<&Member> {
        match self {
            Finding::Named { with, .. } => with.as_ref(),
            _ => None,
        }
    }
}

/// The verdict of a diagnosis: the finding and its figures.
#[derive(Debug, Clone)]
pub struct Verdict {
    pub finding: Finding,
    /// Residual RMS before/after adding the effect, in-sample (mm).
    pub rms_before: f64,
    pub rms_after: f64,
    pub max_before: f64,
    pub max_after: f64,
    /// Same on withheld points (mm).
    pub cv_rms_before: f64,
    pub cv_rms_after: f64,
    /// Smallest RMS of an effect's unabsorbed part that can be named: `k σ` (mm).
    pub detection_limit: f64,
    /// The noise σ used (mm).
    pub sigma: f64,
    /// Fitted parameters of the named effect (of the pair: `<effect>.<name>`).
    pub parameters: BTreeMap<String, Estimate>,
    /// Significant candidates whose unabsorbed part is below the detection limit.
    pub possible_below_limit: Vec<Effect>,
    /// Per curve, before/after.
    pub per_curve: Vec<CurveShrink>,
    /// One sentence saying why.
    pub reason: String,
}

impl Verdict {
    /// The verdict in one word.
    pub fn id(&self) -> VerdictId {
        self.finding.id()
    }
    /// A plain-language name of the verdict.
    pub fn plain_name(&self) -> &'static str {
        self.id().plain_name()
    }

    /// The fitted parameter `name` of the named `effect`: keyed by its own name for one effect,
    /// `<effect>.<name>` in a pair ([`crate::gap::which`]'s keys).
    pub fn parameter(&self, effect: Effect, name: &str) -> Option<&Estimate> {
        if self.finding.with().is_some() {
            self.parameters.get(&format!("{effect}.{name}"))
        } else {
            self.parameters.get(name)
        }
    }
}

/// The flat JSON of a verdict (module doc).
#[derive(Serialize)]
struct VerdictJson<'a> {
    kind: &'static str,
    effect: VerdictId,
    plain_name: &'static str,
    equivalent: &'a [Effect],
    rms_before: f64,
    rms_after: f64,
    max_before: f64,
    max_after: f64,
    cv_rms_before: f64,
    cv_rms_after: f64,
    detection_limit: f64,
    sigma: f64,
    parameters: &'a BTreeMap<String, Estimate>,
    possible_below_limit: &'a [Effect],
    partial: Option<Effect>,
    with: Vec<Effect>,
    with_equivalent: &'a [Effect],
    per_curve: &'a [CurveShrink],
    reason: &'a str,
}

impl Serialize for Verdict {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let f = &self.finding;
        VerdictJson {
            kind: match f {
                Finding::Noise => "noise",
                Finding::Unexplained { .. } => "unexplained",
                Finding::Named { .. } => "named",
            },
            effect: f.id(),
            plain_name: self.plain_name(),
            equivalent: f.equivalent(),
            rms_before: self.rms_before,
            rms_after: self.rms_after,
            max_before: self.max_before,
            max_after: self.max_after,
            cv_rms_before: self.cv_rms_before,
            cv_rms_after: self.cv_rms_after,
            detection_limit: self.detection_limit,
            sigma: self.sigma,
            parameters: &self.parameters,
            possible_below_limit: &self.possible_below_limit,
            partial: match f {
                Finding::Unexplained { partial } => *partial,
                _ => None,
            },
            with: f.with().map(|m| m.effect).into_iter().collect(),
            with_equivalent: f.with().map_or(&[], |m| m.equivalent.as_slice()),
            per_curve: &self.per_curve,
            reason: &self.reason,
        }
        .serialize(s)
    }
}

/// Inputs of the decision beyond the candidate fits.
pub struct DecisionInput<'a> {
    pub fits: &'a [CandidateFit],
    pub baseline_cv_score: f64,
    pub baseline_structured: bool,
    pub baseline_structure_rms: f64,
    /// `(σ̂, ceiling)` (mm) when σ̂ is more than noise can plausibly be
    /// ([`crate::measurement::noise::NoiseEstimate::implausible`]).
    pub implausible_noise: Option<(f64, f64)>,
    pub sigma: f64,
    pub detect_factor: f64,
    pub rms_before: f64,
    pub max_before: f64,
    pub cv_rms_before: f64,
    pub baseline_per_curve: Vec<CurveShrink>,
}

/// Applies the decision rule.
pub fn decide(d: &DecisionInput) -> Verdict {
    let k = d.detect_factor;
    let limit = k * d.sigma;
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
    let possible_below_limit: Vec<Effect> = d
        .fits
        .iter()
        .filter(|f| f.evidence.significant && !f.evidence.above_limit)
        .map(|f| f.effect)
        .collect();
    let unchanged = |finding: Finding, reason: String| Verdict {
        finding,
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
        per_curve: d.baseline_per_curve.clone(),
        reason,
    };
    let Some(w) = winner else {
        return if let Some((estimated, ceiling)) = d.implausible_noise {
            unchanged(
                Finding::Unexplained { partial: None },
                format!(
                    "the point-to-point scatter of the residual, σ̂ = {:.1} µm, is more than a CMM and a finished flank give (at most {:.1} µm): it is structure at the spacing of the points, and no candidate explains it",
                    estimated * 1e3,
                    ceiling * 1e3
                ),
            )
        } else if d.baseline_structured {
            unchanged(
                Finding::Unexplained { partial: None },
                format!(
                    "the residual has {:.1} µm RMS of structure beyond noise (> {k}σ = {:.1} µm) and no candidate explains it",
                    d.baseline_structure_rms * 1e3,
                    limit * 1e3
                ),
            )
        } else {
            unchanged(
                Finding::Noise,
                format!(
                    "no candidate improves the fit beyond noise: nothing above the detection limit of {:.1} µm RMS ({k}σ, σ = {:.2} µm)",
                    limit * 1e3,
                    d.sigma * 1e3
                ),
            )
        };
    };
    let limit = k * w.evidence.sigma;
    if w.evidence.structure_after > k * w.evidence.sigma_smooth {
        return unchanged(
            Finding::Unexplained {
                partial: Some(w.effect),
            },
            format!(
                "`{}` explains part of the gap, but {:.1} µm RMS of structure remains (> {k}σ = {:.1} µm)",
                w.effect,
                w.evidence.structure_after * 1e3,
                limit * 1e3
            ),
        );
    }
    Verdict {
        finding: Finding::Named {
            effect: w.effect,
            equivalent: equivalents(d.fits, w),
            with: None,
        },
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
        per_curve: w.per_curve.clone(),
        reason: format!(
            "significant after Bonferroni over the candidates (p = {:.2e}), its visible part is {:.1} µm RMS (> {k}σ = {:.1} µm), best on withheld points, and the residual left is noise",
            w.evidence.p_bonferroni,
            w.evidence.unabsorbed_rms * 1e3,
            limit * 1e3
        ),
    }
}

/// Candidates this part cannot tell apart from the winner `w`: those whose unabsorbed span
/// reproduces `w`'s visible effect (cosine ≥ [`EQUIVALENT_COS`]) or whose fit is not
/// significantly worse (χ²₁ rule of the module doc).
pub fn equivalents(fits: &[CandidateFit], w: &CandidateFit) -> Vec<Effect> {
    // Noise variance for the comparison: the larger of σ² and the winner's mean square.
    let sigma2 = (w.rms * w.rms)
        .max(w.evidence.sigma * w.evidence.sigma)
        .max(f64::MIN_POSITIVE);
    let rss_w = w.rms * w.rms * w.unabsorbed_effect.len() as f64;
    fits.iter()
        .filter(|f| f.effect != w.effect && f.evidence.added_rank > 0)
        .filter(|f| {
            let cos = cos_to_span(&w.unabsorbed_effect, &f.unabsorbed_basis);
            let rss_f = f.rms * f.rms * f.unabsorbed_effect.len() as f64;
            cos >= EQUIVALENT_COS || (rss_f - rss_w) / sigma2 < CHI2_1_95
        })
        .map(|f| f.effect)
        .collect()
}

/// The verdict of an accepted pair ([`crate::gap::pairs`]): its first member named, the second under
/// `with`, the pair's figures and parameters (of a pair whose second member is below the limit,
/// `weak_pair_verdict`). `before` is the single-candidate verdict.
pub fn pair_verdict(
    before: &Verdict,
    fits: &[CandidateFit],
    pair: &PairFit,
    detect_factor: f64,
) -> Verdict {
    if pair.second_below_limit {
        return weak_pair_verdict(before, fits, pair, detect_factor);
    }
    let f = &pair.fit;
    let fit_of = |e: Effect| fits.iter().find(|c| c.effect == e);
    let limit = detect_factor * f.evidence.sigma;
    let member_equivalent = |m: Effect, swaps: &[Effect], other: Effect| match fit_of(m) {
        Some(mf) => pair_equivalent(fits, mf, swaps, other),
        None => swaps.to_vec(),
    };
    Verdict {
        finding: Finding::Named {
            effect: pair.first,
            equivalent: member_equivalent(pair.first, &pair.first_equivalent, pair.second),
            with: Some(Member {
                effect: pair.second,
                equivalent: member_equivalent(pair.second, &pair.second_equivalent, pair.first),
            }),
        },
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
            .filter(|c| **c != pair.first && **c != pair.second)
            .copied()
            .collect(),
        per_curve: f.per_curve.clone(),
        reason: format!(
            "{}; `{}` together with `{}` does: `{}` adds {:.1} µm RMS beyond the baseline and `{}` (F-test p = {:.2e}, Bonferroni over the pairs tried), the pair predicts withheld points better than either alone, and the residual left is noise",
            match &before.finding {
                Finding::Named { effect, with: None, .. } => format!(
                    "`{effect}` alone leaves a second effect visible (more than {detect_factor} σ of it)"
                ),
                _ => "no single candidate explains the gap".to_string(),
            },
            pair.first,
            pair.second,
            pair.second,
            pair.added_rms * 1e3,
            pair.first,
            pair.p_bonferroni,
        ),
    }
}

/// The verdict of a pair whose second member is significant but below the detection limit
/// ([`crate::gap::pairs`], `second_below_limit`): the first member named alone, with its own fit's
/// figures (what the final answer fits) and its parameters from the joint fit, against the pair's
/// σ (the second effect no longer inflates it); the second first among the effects possible below
/// the limit.
fn weak_pair_verdict(before: &Verdict, fits: &[CandidateFit], pair: &PairFit, k: f64) -> Verdict {
    let f = &pair.fit;
    let limit = k * f.evidence.sigma;
    let Some(first) = fits
        .iter()
        .find(|c| c.effect == pair.first && c.with.is_none())
    else {
        return before.clone();
    };
    let mut possible = vec![pair.second];
    possible.extend(
        before
            .possible_below_limit
            .iter()
            .filter(|c| **c != pair.first && **c != pair.second),
    );
    Verdict {
        finding: Finding::Named {
            effect: pair.first,
            equivalent: pair_equivalent(fits, first, &pair.first_equivalent, pair.second),
            with: None,
        },
        rms_before: before.rms_before,
        rms_after: first.rms,
        max_before: before.max_before,
        max_after: first.max_abs,
        cv_rms_before: before.cv_rms_before,
        cv_rms_after: first.cv_rms,
        detection_limit: limit,
        sigma: f.evidence.sigma,
        // the named member's parameters from the joint fit: the second effect is significant, so
        // leaving it out would bias them (a servo lag fitted alone holds the common rounding)
        parameters: member_parameters(&f.parameters, pair.first),
        possible_below_limit: possible,
        per_curve: first.per_curve.clone(),
        reason: format!(
            "no single candidate explains the gap alone: `{}` leaves `{}` in its residual, which inflates its σ; fitted together, `{}` is significant and visible ({:.1} µm RMS > {k}σ = {:.1} µm, σ of the pair's fit) and the residual left is noise, while `{}` adds {:.1} µm RMS (F-test p = {:.2e}, Bonferroni over the pairs tried): significant but below the detection limit, so it is not named",
            pair.first,
            pair.second,
            pair.first,
            pair.first_added_rms * 1e3,
            limit * 1e3,
            pair.second,
            pair.added_rms * 1e3,
            pair.p_bonferroni,
        ),
    }
}

/// The parameters of `member` in a pair's fit (keyed `<effect>.<name>`), keyed by their name.
fn member_parameters(
    pair: &BTreeMap<String, Estimate>,
    member: Effect,
) -> BTreeMap<String, Estimate> {
    let prefix = format!("{member}.");
    // inserted one by one (a `collect` into the map would bring a sort into the page's wasm)
    let mut out = BTreeMap::new();
    for (k, e) in pair {
        if let Some(name) = k.strip_prefix(&prefix) {
            out.insert(name.to_string(), *e);
        }
    }
    out
}

/// Equivalents of one member `m` of a pair: the swaps that fit as well (`swaps`) and the candidates
/// whose unabsorbed span reproduces `m`'s visible effect; never the pair's `other` member.
fn pair_equivalent(
    fits: &[CandidateFit],
    m: &CandidateFit,
    swaps: &[Effect],
    other: Effect,
) -> Vec<Effect> {
    let mut out: Vec<Effect> = swaps.to_vec();
    for f in fits {
        if f.effect != m.effect
            && f.effect != other
            && f.evidence.added_rank > 0
            && !out.contains(&f.effect)
            && cos_to_span(&m.unabsorbed_effect, &f.unabsorbed_basis) >= EQUIVALENT_COS
        {
            out.push(f.effect);
        }
    }
    out
}
