//! The serialisable report of a diagnosis (the JSON of `testpiece diagnose`, shared/spec/cli.md)
//! and its plain-language summary.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::gap::equivalence::Equivalence;
use crate::gap::location::{WhereEntry, WhereReport};
use crate::gap::pairs::PairFit;
use crate::gap::verdict::{Finding, Verdict};
use crate::gap::which::{CandidateFit, Estimate};
use crate::measurement::layout::{sentence as layout_sentence, Layout};
use crate::measurement::noise::NoiseEstimate;
use crate::parameter::Effect;

/// The baseline fit (location errors only).
#[derive(Debug, Clone, Serialize)]
pub struct BaselineReport {
    /// Residual RMS (mm).
    pub rms: f64,
    pub max_abs: f64,
    /// RMS on withheld points (mm).
    pub cv_rms: f64,
    pub parameters: BTreeMap<String, Estimate>,
    pub rank: usize,
    pub condition: f64,
    pub points: usize,
}

/// Everything a diagnosis found.
#[derive(Debug, Clone, Serialize)]
pub struct DiagnosisReport {
    pub baseline: BaselineReport,
    /// WHERE: residual per curve, region, lean, reversal.
    #[serde(rename = "where")]
    pub where_: Vec<WhereEntry>,
    /// Noise versus structure, trends.
    pub structure: WhereReport,
    /// WHICH: every candidate, best (lowest `cv_score`) first.
    pub candidates: Vec<CandidateFit>,
    /// Candidate pairs this part can hardly tell apart.
    pub equivalences: Vec<Equivalence>,
    /// Names of the folds of points withheld for cross-validation.
    pub folds: Vec<String>,
    pub verdict: Verdict,
    /// The pair behind the verdict when two effects together explain the gap ([`crate::gap::pairs`]).
    pub pair: Option<PairFit>,
    /// The measured points' layout and what it cannot tell ([`crate::measurement::layout`]).
    pub layout: Layout,
    /// Plain-language summary; the first line is `Verdict: <plain name> (`<id>`)`.
    pub summary: String,
}

/// Effect ids joined by commas.
fn ids(effects: &[Effect]) -> String {
    effects
        .iter()
        .map(|e| e.id())
        .collect::<Vec<_>>()
        .join(", ")
}

fn um(x: f64) -> String {
    format!("{:.1} µm", x * 1e3)
}

/// Below this p-value of the residual's χ² against σ, a residual whose structure is under the
/// detection limit is not called "consistent with noise": the χ² test says it is more than noise
/// alone (a C backlash of 0.1 mrad on a 20,000-point scan: 1.1 µm of structure against a limit
/// of 3.7 µm, χ² 30,603 on 19,992 degrees of freedom). The words only: no verdict reads it.
pub const NOISE_CHI2_ALPHA: f64 = 1e-3;

/// What the structure beyond noise of the baseline residual is, in words: `structured` above the
/// detection limit `limit` (mm); under it, consistent with noise unless the residual's χ² test
/// (`(χ², degrees of freedom, p)`) rejects noise alone ([`NOISE_CHI2_ALPHA`]), which is then
/// said with its figures.
fn structure_words(structured: bool, chi2: (f64, usize, f64), limit: f64) -> String {
    let (chi2, dof, chi2_p) = chi2;
    if structured {
        "structured".into()
    } else if chi2_p < NOISE_CHI2_ALPHA {
        let p = if chi2_p < 1e-99 {
            "p < 1e-99".to_string()
        } else {
            format!("p = {chi2_p:.1e}")
        };
        format!(
            "below the detection limit of {}, but more than noise alone: χ² {:.0} on {} \
             degrees of freedom, {p}",
            um(limit),
            chi2,
            dof
        )
    } else {
        "consistent with noise".into()
    }
}

/// The verdict in one line, `Verdict: <plain name> (`<id>`)` (and the pair's second effect):
/// the first line of [`summary`], and the page's headline.
pub fn verdict_line(v: &Verdict) -> String {
    let mut s = format!("Verdict: {} (`{}`)", v.plain_name(), v.id());
    if let Some(w) = v.finding.with() {
        s += &format!(" together with {} (`{}`)", w.effect.plain_name(), w.effect);
    }
    s
}

/// How σ was reached, in words: the estimator, the CMM's floor and the part's own scatter, the
/// detection limit, and a σ̂ more than noise can be.
fn noise_sentence(n: &NoiseEstimate, sigma: f64, limit: f64) -> String {
    let how = match (n.given, n.part_scatter) {
        (Some(cmm), None) => format!(
            "the CMM's {}; the data's σ̂ = {} ({}) is not significantly above it",
            um(cmm),
            um(n.estimated),
            n.estimator.words()
        ),
        (Some(cmm), Some(part)) => format!(
            "the CMM's {} and the part's own scatter {} together: σ̂ from the data ({})",
            um(cmm),
            um(part),
            n.estimator.words()
        ),
        (None, _) if (sigma - n.used).abs() > 1e-9 * n.used.max(1e-12) => format!(
            "the residual once the named effect is fitted; the part's σ̂ before it is {}, from {}",
            um(n.used),
            n.estimator.words()
        ),
        (None, _) => format!("estimated from the data: {}", n.estimator.words()),
    };
    let mut s = format!(
        "Noise: σ = {} ({how}); detection limit {} RMS of an effect's visible part.\n",
        um(sigma),
        um(limit)
    );
    if n.implausible {
        s += &format!(
            "Check: σ̂ = {} is more than noise can be on a part like this one (at most {}: {}): \
             the point-to-point variation of the residual holds structure, and the part is \
             not called noise.{}\n",
            um(n.estimated),
            um(n.ceiling),
            match n.given {
                Some(_) => "the CMM's figure and a finished flank's scatter",
                None => "a CMM and a finished flank together; give the CMM's figure (--sigma or --mpe) for a closer bound",
            },
            " The decisions use that bound as σ."
        );
    }
    s
}

/// The fitted shape of a named family, with its 95 % interval (an open end: the part does not
/// bound the shape on that side).
fn shape_sentence(e: Effect, sh: &crate::gap::shape::ShapeFit) -> String {
    let v = |x: f64| {
        if x.is_infinite() {
            "∞ (linear)".to_string()
        } else {
            format!("{x:.3}")
        }
    };
    let low = if sh.low_open {
        format!("≤ {}", v(sh.low))
    } else {
        v(sh.low)
    };
    let high = if sh.high_open {
        format!("≥ {}", v(sh.high))
    } else {
        v(sh.high)
    };
    let (what, unit) = match sh.name {
        "tau" => ("lag after a reversal", " mm of tool-tip path"),
        _ => ("warm-up constant, a fraction of the machining time", ""),
    };
    // the profiled parameter at the member that fits best: the warm-up's pause between the
    // passes, a backlash's overshoot or take-up
    let pause = sh.profiled.as_ref().map_or(String::new(), |p| match p.name {
        "pause" => format!(
            ", with a pause between the passes of {:.2} of the machining time (the grid's value that fits best)",
            p.value
        ),
        "overshoot" if p.value > 0.0 => format!(
            ", settling in second order: the slide overshoots by {:.0} % of the lost motion (damping ζ {:.2}; the grid's value that fits best; the lag is then the natural length)",
            100.0 * p.value,
            crate::parameter::effect::damping_of_overshoot(p.value).unwrap_or(1.0)
        ),
        "overshoot" => ", settling in first order (the interval holds the lags with and without an overshoot)".to_string(),
        _ if p.value > 0.0 => format!(
            ", with the play taken up over a lost motion of {:.3e} (the interval holds the lags with and without it)",
            p.value
        ),
        _ => ", switched at the reversal (the interval holds the lags with and without the play's take-up)".to_string(),
    });
    format!(
        "Shape: `{e}` {what} {} = {}{unit} (95 %: {low} to {high}{unit}; reference {}{pause}; {:.1} effectively independent shapes searched).\n",
        sh.name,
        v(sh.value),
        v(sh.reference),
        sh.effective_shapes
    )
}

/// The plain-language summary of a report (first line: the verdict).
pub fn summary(r: &DiagnosisReport) -> String {
    let v = &r.verdict;
    let f = &v.finding;
    let mut s = verdict_line(v);
    s += "\n";
    s += &format!("Why: {}.\n", v.reason);
    if !v.parameters.is_empty() {
        let ps: Vec<String> = v
            .parameters
            .iter()
            .map(|(k, e)| format!("{k} = {:.4e} ± {:.1e}", e.value, e.std))
            .collect();
        s += &format!("Fitted: {}.\n", ps.join(", "));
    }
    for e in f.effects() {
        if let Some(sh) = r
            .candidates
            .iter()
            .find(|c| c.effect == e && c.with.is_none())
            .and_then(|c| c.shape.as_ref())
        {
            s += &shape_sentence(e, sh);
        }
    }
    if !f.equivalent().is_empty() {
        s += &format!(
            "This part cannot tell it apart from: {}.\n",
            ids(f.equivalent())
        );
    }
    s += &format!(
        "How far: residual RMS {} -> {} in-sample, {} -> {} on withheld points; max {} -> {}.\n",
        um(v.rms_before),
        um(v.rms_after),
        um(v.cv_rms_before),
        um(v.cv_rms_after),
        um(v.max_before),
        um(v.max_after)
    );
    s += &noise_sentence(&r.structure.noise, v.sigma, v.detection_limit);
    s += &format!(
        "Where: baseline residual {} RMS, {} of it beyond noise ({}){}.\n",
        um(r.baseline.rms),
        um(r.structure.structure_rms),
        structure_words(
            r.structure.structured,
            (r.structure.chi2, r.structure.chi2_dof, r.structure.chi2_p),
            v.detection_limit
        ),
        r.structure
            .concentrated_in
            .as_ref()
            .map(|c| format!(", concentrated in {c}"))
            .unwrap_or_default()
    );
    if let Some(w) = f.with().filter(|w| !w.equivalent.is_empty()) {
        s += &format!(
            "In the pair, this part cannot tell `{}` apart from: {}.\n",
            w.effect,
            ids(&w.equivalent)
        );
    }
    if let Finding::Unexplained { partial: Some(p) } = f {
        s += &format!("Partly explained by `{p}`.\n");
    }
    if !v.possible_below_limit.is_empty() {
        s += &format!(
            "Possible, below the detection limit: {}.\n",
            ids(&v.possible_below_limit)
        );
    }
    for e in &r.equivalences {
        s += &format!(
            "Near-equivalent on this part: `{}` and `{}` (cosine {:.3}).\n",
            e.a, e.b, e.cosine
        );
    }
    if let Some(l) = layout_sentence(&r.layout) {
        s += &l;
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Under the detection limit, the residual is called consistent with noise only where its
    /// χ² does not reject noise alone (figures of a clean and a C-backlash 20,000-point scan).
    #[test]
    fn structure_under_the_limit_is_noise_only_when_chi2_agrees() {
        assert_eq!(
            structure_words(true, (30_603.0, 19_992, 0.0), 0.0037),
            "structured"
        );
        assert_eq!(
            structure_words(false, (20_279.0, 19_992, 0.076), 0.0037),
            "consistent with noise"
        );
        assert_eq!(
            structure_words(false, (30_603.0, 19_992, 0.0), 0.0037),
            "below the detection limit of 3.7 µm, but more than noise alone: χ² 30603 on 19992 \
             degrees of freedom, p < 1e-99"
        );
        assert_eq!(
            structure_words(false, (146.4, 92, 2.6e-4), 0.0046),
            "below the detection limit of 4.6 µm, but more than noise alone: χ² 146 on 92 \
             degrees of freedom, p = 2.6e-4"
        );
    }
}
