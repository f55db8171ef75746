//! The final identification: the machine's location errors fitted together with what the
//! diagnosis found, so that the errors reported and exported for compensation are not biased by
//! an effect the baseline leaves out.
//!
//! One answer per part, by the verdict ([`Basis`]):
//! - **named** effect (or the two of a pair): the identification's design `A` (the machine's
//!   location errors, `dR` when forced) is extended by the effect's signature columns `S_e`
//!   (effects.md, per unit of each parameter, named `<id>.<parameter>`), and `[A | S_e]` is
//!   fitted by the same least squares as the baseline (rank, groups, weak directions, std from
//!   the residual of the joint fit). An effect column that the design already holds (e.g.
//!   `tool_radius.dR` when `dR` is forced) or that leaves nothing on the part is not added twice,
//!   and the note says so. Each location error's **shift** from the baseline is
//!   `(x_final − x_baseline) / std_final`. When the verdict lists equivalent effects, the fit is
//!   repeated with each of them in place of the named one and the largest difference of a
//!   location error, in std, is reported ([`Alternative`]): where the equivalence is exact the
//!   location errors do not depend on the choice.
//! - **unexplained**: no effect is fitted (none was accepted; a partial candidate is only
//!   mentioned). The structure is modelled as a correlated error along the tool path
//!   ([`crate::final_fit::structure`]: squared-exponential covariance, amplitude and length by REML, the
//!   white σ of the diagnosis) and the location errors are fitted by generalised least squares
//!   ([`crate::identify::correlated`]). Why this and not the smooth basis as fixed nuisance
//!   columns: the location errors' own signatures are smooth along each curve, so a per-curve
//!   polynomial basis of the diagnosis's degree absorbs most of them and leaves them barely
//!   identifiable; as a random effect with an estimated amplitude the structure widens the std
//!   exactly as much as a structure of that size and scale could move each error, and leaves the
//!   errors determined where the structure is small. The report says the std includes it.
//! - **none**: the baseline stands.
//!
//! `--effects` ([`EffectsChoice`]) overrides the verdict: `none` keeps the baseline, a list of ids
//! forces those effects whatever the diagnosis says.

use std::fmt;
use std::str::FromStr;

use nalgebra::DMatrix;
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::effects::data::{Candidate, PointMeta};
use crate::effects::GapError;
use crate::final_fit::structure::{self, CovarianceForm, StructureCovariance};
use crate::gap::verdict::{Finding, Verdict, VerdictId};
use crate::identify::correlated::{
    identify_correlated, identify_whitened, GroupedLowRank, Whitener,
};
use crate::identify::solve::{rms, Factor};
use crate::identify::{identify, Design, Identification, IdentifyOptions, Observations, Parameter};
use crate::machine::location_errors::TYPICAL_LENGTH_MM;
use crate::parameter::{Effect, ParamId};

/// A signature column whose RMS over the points is below this (mm per unit) leaves nothing on
/// the part: it is not fitted.
pub const NO_SIGNATURE: f64 = 1e-12;
/// Relative norm of an effect column outside the design below which it is already in it.
pub const ALREADY_IN_DESIGN: f64 = 1e-9;
/// Largest difference of a location error between equivalent effects (in std) reported as
/// "does not depend on the choice".
pub const SAME_ANSWER_STD: f64 = 0.1;

/// Which effects the final identification fits with the location errors (`--effects`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum EffectsChoice {
    /// What the diagnosis names (default).
    #[default]
    Auto,
    /// None: the baseline is the answer.
    None,
    /// These effects, whatever the diagnosis says.
    Given(Vec<Effect>),
}

impl FromStr for EffectsChoice {
    type Err = GapError;
    /// `auto`, `none`, or effect ids separated by commas (`backlash_y,setup_error`).
    fn from_str(s: &str) -> Result<Self, GapError> {
        match s.trim() {
            "auto" | "" => Ok(EffectsChoice::Auto),
            "none" => Ok(EffectsChoice::None),
            list => {
                let mut out: Vec<Effect> = Vec::new();
                for id in list.split(',').map(str::trim).filter(|t| !t.is_empty()) {
                    let e: Effect = id.parse()?;
                    if out.contains(&e) {
                        return Err(GapError::DuplicateCandidate(e));
                    }
                    out.push(e);
                }
                Ok(EffectsChoice::Given(out))
            }
        }
    }
}

impl fmt::Display for EffectsChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EffectsChoice::Auto => f.write_str("auto"),
            EffectsChoice::None => f.write_str("none"),
            EffectsChoice::Given(v) => {
                let ids: Vec<&str> = v.iter().map(|e| e.id()).collect();
                f.write_str(&ids.join(","))
            }
        }
    }
}

impl Serialize for EffectsChoice {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.to_string())
    }
}

impl<'de> Deserialize<'de> for EffectsChoice {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

/// What the final answer was fitted with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Basis {
    /// The location errors alone (verdict `none`, `--effects none`, or no diagnosis).
    Baseline,
    /// The location errors with effect columns.
    Effects,
    /// The location errors by generalised least squares with the structure's covariance.
    Structure,
}

/// A location error's shift from the baseline, in std of the final answer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Shift {
    pub parameter: String,
    /// `(final − baseline) / std_final`; `None` without a final std.
    pub std: Option<f64>,
}

/// Shifts in design order, serialised as `{name: shift or null}`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ShiftMap(pub Vec<Shift>);

impl Serialize for ShiftMap {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for x in &self.0 {
            m.serialize_entry(&x.parameter, &x.std)?;
        }
        m.end()
    }
}

impl ShiftMap {
    /// The largest shift in absolute value.
    pub fn largest(&self) -> Option<&Shift> {
        self.0
            .iter()
            .filter(|s| s.std.is_some_and(f64::is_finite))
            .max_by(|a, b| {
                let (x, y) = (a.std.unwrap_or(0.0).abs(), b.std.unwrap_or(0.0).abs());
                x.total_cmp(&y)
            })
    }
}

/// The final fit with an equivalent effect in place of the named one.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Alternative {
    /// The equivalent effect used instead.
    pub effect: Effect,
    /// The location error that differs most from the final answer, and by how much, in std of
    /// the final answer.
    pub parameter: String,
    pub difference_std: f64,
    /// Whether the location errors are the same to [`SAME_ANSWER_STD`].
    pub same_answer: bool,
}

/// How the final answer was obtained (JSON `correction`).
#[derive(Debug, Clone, Serialize)]
pub struct Correction {
    pub basis: Basis,
    /// The `--effects` setting.
    pub choice: EffectsChoice,
    /// The diagnosis verdict id (`none`, `unexplained`, an effect id); `null` without a diagnosis.
    pub verdict: Option<VerdictId>,
    /// The effects fitted with the location errors (ids; empty for the baseline and structure).
    pub effects_included: Vec<Effect>,
    /// The effect parameters added to the design, in design order (serialised by name,
    /// `<id>.<parameter>`).
    #[serde(serialize_with = "names")]
    pub effect_parameters: Vec<ParamId>,
    /// Per location error of the baseline: `(final − baseline) / std_final`.
    pub shift: ShiftMap,
    /// Equivalent effects tried in place of the named one.
    pub alternatives: Vec<Alternative>,
    /// The structure's covariance (basis `structure`).
    pub structure: Option<StructureCovariance>,
    /// Whether the std include an unexplained structure.
    pub std_includes_structure: bool,
    /// What the values were fitted with, as the export's `fitted_with` column: effect ids
    /// joined by `+`, `structure`, or `none`.
    pub fitted_with: String,
    /// The same in words ("fitted with the backlash of the C axis (backlash_c)").
    pub fitted_with_words: String,
    /// What was not added and why, in sentences.
    pub notes: Vec<String>,
    /// The plain-language account (the page's verdict box, the CLI).
    pub summary: String,
    /// What the choice among the candidate models can move each location error by, included
    /// in their std ([`crate::final_fit::model_spread`]); empty when not computed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model_spread: Option<crate::final_fit::model_spread::ModelSpread>,
}

/// Parameters as the list of their names.
fn names<S: Serializer>(ids: &[ParamId], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(ids.iter().map(ParamId::name))
}

/// What the final values were fitted with, for the export: effect ids joined by `+`,
/// `structure`, or `none`.
fn fitted_with(basis: Basis, effects: &[Effect]) -> String {
    match basis {
        Basis::Baseline => "none".to_string(),
        Basis::Structure => "structure".to_string(),
        Basis::Effects => effects.iter().map(|e| e.id()).collect::<Vec<_>>().join("+"),
    }
}

/// The same in words, for the page and the reports.
fn fitted_with_words(basis: Basis, effects: &[Effect]) -> String {
    match basis {
        Basis::Baseline => "the location errors alone (baseline)".to_string(),
        Basis::Structure => {
            "fitted with the unexplained structure as a correlated error (std include it)"
                .to_string()
        }
        Basis::Effects => {
            let names: Vec<String> = effects
                .iter()
                .map(|e| format!("the {} ({e})", e.plain_name()))
                .collect();
            format!("fitted with {}", names.join(" and "))
        }
    }
}

/// What the final identification starts from.
#[derive(Debug, Clone, Copy)]
pub struct CorrectionInput<'a> {
    /// The identification's design (location errors, `dR` when forced).
    pub design: &'a Design,
    pub observations: &'a Observations,
    /// The baseline identification (after its refinement).
    pub baseline: &'a Identification,
    /// The points, same order as the design's rows.
    pub points: &'a [PointMeta],
    /// The candidates' signatures at those points.
    pub candidates: &'a [Candidate],
    /// The diagnosis verdict, when it was made.
    pub verdict: Option<&'a Verdict>,
    /// The part's noise σ of the diagnosis (mm), when it was made: the white noise under a
    /// structure the named effect leaves.
    pub noise_sigma: Option<f64>,
    /// Why effects of the verdict cannot be fitted here (e.g. the diagnosis used another
    /// machine): effect and reason.
    pub unavailable: &'a [(Effect, String)],
    pub options: &'a IdentifyOptions,
    /// The structure's decompositions kept for these points ([`structure::Decompositions`]: a
    /// value the caller holds; a fresh one computes them).
    pub decompositions: &'a structure::Decompositions,
    /// Threads for the structure's estimate (the same numbers whatever their count).
    pub threads: crate::numerics::parallel::Threads,
}

/// The final answer.
#[derive(Debug, Clone)]
pub struct Final {
    /// The design fitted (`A`, or `[A | S_e]`).
    pub design: Design,
    pub identification: Identification,
    /// `Σ^{-½}` of the structure's covariance (basis `structure`): a refinement must work on the
    /// whitened problem.
    pub whitener: Option<crate::identify::correlated::Whitener>,
    pub correction: Correction,
}

/// The effect columns added to `design` for `effects`: ids [`ParamId::Effect`] (names
/// `<id>.<parameter>`, unit from effects.md), typical size the value that leaves 0.01 mm RMS on
/// the part (like a typical location error). Returns the design, the added parameters and the
/// notes of what was not added.
pub fn with_effects(
    design: &Design,
    candidates: &[Candidate],
    effects: &[Effect],
) -> Result<(Design, Vec<ParamId>, Vec<String>), GapError> {
    let mut d = design.clone();
    let mut added = Vec::new();
    let mut notes = Vec::new();
    for &e in effects {
        let c = candidates
            .iter()
            .find(|c| c.effect == e)
            .ok_or(GapError::NotModelled(e))?;
        for (j, id) in e.parameter_ids().into_iter().enumerate() {
            let name = id.name();
            let col: Vec<f64> = c.signature.matrix.column(j).iter().copied().collect();
            let size = rms(&col);
            if size < NO_SIGNATURE {
                notes.push(format!(
                    "`{name}` leaves no deviation on this part (its signature is zero here): not fitted."
                ));
                continue;
            }
            let outside = Factor::new(d.matrix(), None)
                .unabsorbed_vec(&nalgebra::DVector::from_column_slice(&col))
                .norm();
            let norm = size * (col.len() as f64).sqrt();
            if outside < ALREADY_IN_DESIGN * norm {
                notes.push(format!(
                    "`{name}` is already a column of the design (a combination of {}): fitted once.",
                    d.names().join(", ")
                ));
                continue;
            }
            d = d.with_column(Parameter::new(id.clone(), TYPICAL_LENGTH_MM / size), &col)?;
            added.push(id);
        }
    }
    Ok((d, added, notes))
}

/// The note of a servo lag fitted with the common rounding ([`with_rounding`]).
const NUISANCE_ROUNDING: &str = "`servo_common.L2` is fitted with the servo lag: the axes lag together, and their lag rounds the path.";

/// `effects`, and `servo_common` when they hold a servo lag without it and the part has its
/// column: the lag's estimate with the rounding every lagging axis shares
/// ([`crate::gap::which`]'s candidate fit does the same).
fn with_rounding(candidates: &[Candidate], effects: &[Effect]) -> Vec<Effect> {
    let mut out = effects.to_vec();
    let lag = effects.iter().any(|e| matches!(e, Effect::ServoLag(_)));
    if lag
        && !effects.contains(&Effect::ServoCommon)
        && candidates.iter().any(|c| c.effect == Effect::ServoCommon)
    {
        out.push(Effect::ServoCommon);
    }
    out
}

/// The effects to fit for `choice` and the verdict, or the reason there are none.
fn chosen(input: &CorrectionInput, choice: &EffectsChoice) -> (Basis, Vec<Effect>, Vec<String>) {
    chosen_by(input.verdict, input.unavailable, choice)
}

/// The basis [`correct`] fits the final answer on, from the verdict, the effects that cannot be
/// fitted and the choice alone (not from any fit): what can be prepared for it before the
/// baseline identification is made.
pub fn basis_of(
    verdict: Option<&Verdict>,
    unavailable: &[(Effect, String)],
    choice: &EffectsChoice,
) -> Basis {
    chosen_by(verdict, unavailable, choice).0
}

/// [`chosen`]'s rule on its inputs: the basis, the effects fitted and the notes.
fn chosen_by(
    verdict: Option<&Verdict>,
    unavailable: &[(Effect, String)],
    choice: &EffectsChoice,
) -> (Basis, Vec<Effect>, Vec<String>) {
    match choice {
        EffectsChoice::None => (
            Basis::Baseline,
            Vec::new(),
            vec!["--effects none: the baseline identification is the answer.".to_string()],
        ),
        EffectsChoice::Given(v) => (Basis::Effects, v.clone(), Vec::new()),
        EffectsChoice::Auto => match verdict.map(|v| &v.finding) {
            None => (
                Basis::Baseline,
                Vec::new(),
                vec!["No diagnosis was made: the errors are not corrected for any effect.".into()],
            ),
            Some(Finding::Noise) => (Basis::Baseline, Vec::new(), Vec::new()),
            Some(Finding::Unexplained { .. }) => (Basis::Structure, Vec::new(), Vec::new()),
            Some(f @ Finding::Named { .. }) => {
                let effects = f.effects();
                let missing: Vec<String> = effects
                    .iter()
                    .filter_map(|e| {
                        unavailable.iter().find(|(u, _)| u == e).map(|(_, why)| {
                            format!("`{e}` cannot be fitted with these errors: {why}")
                        })
                    })
                    .collect();
                if missing.is_empty() {
                    (Basis::Effects, effects, Vec::new())
                } else {
                    let mut notes = missing;
                    notes.push("The errors are NOT corrected for the named effect.".into());
                    (Basis::Baseline, Vec::new(), notes)
                }
            }
        },
    }
}

/// The shift of each baseline parameter, in std of the final answer.
pub fn shifts(baseline: &Identification, fin: &Identification) -> ShiftMap {
    ShiftMap(
        baseline
            .parameters
            .0
            .iter()
            .map(|b| {
                let f = fin.parameters.of(&b.id);
                let std =
                    f.and_then(|f| f.std.filter(|s| *s > 0.0).map(|s| (f.value - b.value) / s));
                Shift {
                    parameter: b.name(),
                    std,
                }
            })
            .collect(),
    )
}

/// The final identification for `choice` (module doc).
pub fn correct(input: &CorrectionInput, choice: &EffectsChoice) -> Result<Final, GapError> {
    let (basis, effects, mut notes) = chosen(input, choice);
    let verdict = input.verdict.map(Verdict::id);
    let base_ids = input.design.ids();
    let (design, identification, added, whitener, structure) = match basis {
        Basis::Baseline => (
            input.design.clone(),
            input.baseline.clone(),
            Vec::new(),
            None,
            None,
        ),
        Basis::Effects => {
            let fitted = with_rounding(input.candidates, &effects);
            if fitted.len() > effects.len() {
                notes.push(NUISANCE_ROUNDING.to_string());
            }
            let (d, added, n) = with_effects(input.design, input.candidates, &fitted)?;
            notes.extend(n);
            let id = identify(&d, input.observations, input.options)?;
            match left_structured(&id, input.noise_sigma) {
                // the effect leaves structure beyond the part's noise (its shape is not quite
                // the part's): that structure as a correlated error, as for `unexplained`
                Some(sigma) => match fit_with_structure(input, &d, sigma) {
                    Ok((sid, w, s)) if s.amplitude > 0.0 => {
                        notes.push(format!(
                            "The named effect leaves structure beyond the noise (residual {:.1} µm RMS, σ = {:.1} µm): it is fitted as a correlated error with the effect, and the std include it.",
                            id.residual.rms * 1e3,
                            sigma * 1e3
                        ));
                        (d, sid, added, Some(w), Some(s))
                    }
                    _ => (d, id, added, None, None),
                },
                None => (d, id, added, None, None),
            }
        }
        Basis::Structure => {
            let sigma = input
                .options
                .sigma
                .or(input.verdict.map(|v| v.sigma))
                .unwrap_or(0.0);
            let (id, w, s) = fit_with_structure(input, input.design, sigma)?;
            (input.design.clone(), id, Vec::new(), Some(w), Some(s))
        }
    };
    let shift = shifts(input.baseline, &identification);
    let alternatives = match (basis, input.verdict.map(|v| &v.finding), choice) {
        (Basis::Effects, Some(f @ Finding::Named { effect, .. }), EffectsChoice::Auto) => {
            alternatives(input, &identification, &base_ids, *effect, f)?
        }
        _ => Vec::new(),
    };
    let effects_included = match basis {
        Basis::Effects => effects.clone(),
        _ => Vec::new(),
    };
    let mut correction = Correction {
        basis,
        choice: choice.clone(),
        verdict,
        effects_included,
        effect_parameters: added,
        shift,
        alternatives,
        std_includes_structure: structure.is_some(),
        fitted_with: fitted_with(basis, &effects),
        fitted_with_words: fitted_with_words(basis, &effects),
        structure,
        notes,
        summary: String::new(),
        model_spread: None,
    };
    correction.summary = summary(&correction, input.baseline, &identification);
    Ok(Final {
        design,
        identification,
        whitener,
        correction,
    })
}

/// The part's noise σ when the residual of `id` is significantly above it (χ² on its degrees of
/// freedom, one-sided at 1 %).
fn left_structured(id: &Identification, noise: Option<f64>) -> Option<f64> {
    let sigma = noise.filter(|s| *s > 0.0 && s.is_finite())?;
    let dof = id.dof as f64;
    let rss = id.residual.rms.powi(2) * id.points_used as f64;
    (dof > 0.0 && crate::numerics::stats::chi2_sf(rss / (sigma * sigma), dof) < 0.01)
        .then_some(sigma)
}

/// The location errors (and the columns of `design`) fitted by generalised least squares with
/// the residual's structure as a correlated error along the tool path (REML,
/// [`crate::final_fit::structure`]) on white noise `sigma`.
fn fit_with_structure(
    input: &CorrectionInput,
    design: &Design,
    sigma: f64,
) -> Result<
    (
        Identification,
        crate::identify::correlated::Whitener,
        StructureCovariance,
    ),
    GapError,
> {
    // Points of weight 0 (outliers) take no part in the structure's estimate and are
    // not correlated with the others.
    let obs = input.observations;
    let used: Vec<usize> = (0..obs.len()).filter(|&i| obs.weight(i) > 0.0).collect();
    let used_points: Vec<PointMeta> = used.iter().map(|&i| input.points[i].clone()).collect();
    let used_y: Vec<f64> = used.iter().map(|&i| obs.deviation[i]).collect();
    let s = structure::estimate(
        &used_points,
        &design.matrix().select_rows(&used),
        &used_y,
        sigma,
        input.decompositions,
        input.threads,
    )
    .ok_or(GapError::StructureNotEstimated {
        sigma,
        points: used.len(),
    })?;
    let n = obs.len();
    let c = match &s.form {
        CovarianceForm::Dense(m) => {
            let mut full = DMatrix::<f64>::identity(n, n) * s.white_sigma.powi(2);
            for (a, &i) in used.iter().enumerate() {
                for (b, &j) in used.iter().enumerate() {
                    full[(i, j)] = m[(a, b)];
                }
            }
            identify_correlated(
                design,
                input.observations,
                &full,
                s.white_sigma,
                input.options,
            )?
        }
        // A large part: Σ^{-½} in closed form on the groups, an excluded point in none.
        CovarianceForm::Grouped { group, scale, v, d } => {
            let s2 = s.white_sigma.powi(2);
            let mut of_point = vec![None; n];
            for (a, &i) in used.iter().enumerate() {
                of_point[i] = Some(group[a]);
            }
            let w = Whitener::LowRank(GroupedLowRank {
                white_variance: s2,
                group: of_point,
                scale: scale.clone(),
                v: v.clone(),
                g: d.iter()
                    .map(|dk| 1.0 / (1.0 + dk / s2).sqrt() - 1.0)
                    .collect(),
            });
            identify_whitened(design, input.observations, w, s.white_sigma, input.options)?
        }
    };
    Ok((c.identification, c.whitener, s))
}

/// The final fit with each equivalent of the named effect in its place.
fn alternatives(
    input: &CorrectionInput,
    fin: &Identification,
    base_ids: &[ParamId],
    named: Effect,
    finding: &Finding,
) -> Result<Vec<Alternative>, GapError> {
    let mut out = Vec::new();
    for &alt in finding.equivalent() {
        if !input.candidates.iter().any(|c| c.effect == alt) {
            continue;
        }
        let effects: Vec<Effect> = finding
            .effects()
            .into_iter()
            .map(|e| if e == named { alt } else { e })
            .collect();
        let (d, _, _) = with_effects(
            input.design,
            input.candidates,
            &with_rounding(input.candidates, &effects),
        )?;
        let id = identify(&d, input.observations, input.options)?;
        let mut worst = (String::new(), 0.0f64);
        for p in base_ids {
            let (Some(a), Some(b)) = (fin.parameters.of(p), id.parameters.of(p)) else {
                continue;
            };
            let Some(s) = a.std.filter(|s| *s > 0.0) else {
                continue;
            };
            let d = (b.value - a.value).abs() / s;
            if d >= worst.1 {
                worst = (p.name(), d);
            }
        }
        out.push(Alternative {
            effect: alt,
            parameter: worst.0,
            difference_std: worst.1,
            same_answer: worst.1 <= SAME_ANSWER_STD,
        });
    }
    Ok(out)
}

/// The plain-language account of a correction of `baseline` into `fin`.
pub fn summary(c: &Correction, baseline: &Identification, fin: &Identification) -> String {
    let mut s = match c.basis {
        Basis::Baseline => match c.verdict {
            Some(VerdictId::Noise) if c.choice == EffectsChoice::Auto => {
                "The location errors are the baseline identification: the diagnosis finds no \
                 unmodelled effect above the detection limit in its residual."
                    .to_string()
            }
            _ => "The location errors are the baseline identification (not corrected for any \
                  effect)."
                .to_string(),
        },
        Basis::Effects => {
            let names: Vec<String> = c
                .effects_included
                .iter()
                .map(|e| format!("{} (`{e}`)", e.plain_name()))
                .collect();
            let mut s = format!(
                "The location errors are fitted together with the {}{}.",
                names.join(" and the "),
                if c.choice == EffectsChoice::Auto {
                    " that the diagnosis names"
                } else {
                    ", as asked (--effects)"
                }
            );
            let ps: Vec<String> = c
                .effect_parameters
                .iter()
                .filter_map(|n| fin.parameters.of(n))
                .map(|p| {
                    format!(
                        "{} = {:.4e}{} {}",
                        p.name(),
                        p.value,
                        p.std.map_or(String::new(), |x| format!(" ± {x:.1e}")),
                        p.unit()
                    )
                })
                .collect();
            if !ps.is_empty() {
                s += &format!(" Effect: {}.", ps.join(", "));
            }
            s
        }
        Basis::Structure => {
            let st = c.structure.as_ref();
            format!(
                "The residual is structured and no candidate explains it: the location errors are \
                 fitted by generalised least squares with that structure as a correlated error \
                 along the tool path (amplitude {:.1} µm, correlation length {:.0} mm, on white \
                 noise σ = {:.1} µm), and their std include it.",
                st.map_or(f64::NAN, |s| s.amplitude * 1e3),
                st.map_or(f64::NAN, |s| s.length),
                st.map_or(f64::NAN, |s| s.white_sigma * 1e3),
            )
        }
    };
    if c.basis != Basis::Baseline {
        if let Some(big) = c.shift.largest() {
            let what = match c.basis {
                Basis::Effects => format!(
                    "once {} was fitted",
                    c.effects_included
                        .iter()
                        .map(|e| e.id())
                        .collect::<Vec<_>>()
                        .join(" and ")
                ),
                _ => "with the structure's covariance".to_string(),
            };
            s += &format!(
                " Largest change from the baseline: {} moved by {:.1} std {what}.",
                big.parameter,
                big.std.unwrap_or(0.0)
            );
        }
        let grown: Vec<f64> = baseline
            .parameters
            .0
            .iter()
            .filter_map(|b| {
                let f = fin.parameters.of(&b.id)?;
                Some(f.std? / b.std.filter(|x| *x > 0.0)?)
            })
            .collect();
        if let (Some(lo), Some(hi)) = (
            grown.iter().copied().reduce(f64::min),
            grown.iter().copied().reduce(f64::max),
        ) {
            s += &format!(" Their std are {lo:.2}x to {hi:.2}x those of the baseline.");
        }
    }
    for a in &c.alternatives {
        s += &if a.same_answer {
            format!(
                " With the equivalent `{}` instead, the location errors are the same (largest \
                 difference {:.2} std, {}).",
                a.effect, a.difference_std, a.parameter
            )
        } else {
            format!(
                " With the equivalent `{}` instead, {} differs by {:.1} std: the part cannot \
                 choose between them, and neither can the location errors.",
                a.effect, a.parameter, a.difference_std
            )
        };
    }
    for n in &c.notes {
        s += " ";
        s += n;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::data::NamedColumns;
    use crate::machine::AxisName;

    fn candidate(effect: Effect) -> Candidate {
        Candidate::new(
            effect,
            NamedColumns::try_new(effect.parameter_ids(), DMatrix::from_element(3, 1, 1.0))
                .unwrap(),
        )
    }

    /// A servo lag is fitted with the rounding when the part has its column, once; nothing
    /// else is.
    #[test]
    fn a_servo_lag_brings_the_rounding_into_the_final_fit() {
        let lag = Effect::ServoLag(AxisName::Y);
        let with = [candidate(lag), candidate(Effect::ServoCommon)];
        assert_eq!(with_rounding(&with, &[lag]), vec![lag, Effect::ServoCommon]);
        assert_eq!(
            with_rounding(&with, &[lag, Effect::ServoCommon]),
            vec![lag, Effect::ServoCommon]
        );
        assert_eq!(with_rounding(&with[..1], &[lag]), vec![lag]);
        let backlash = Effect::Backlash(AxisName::C);
        assert_eq!(with_rounding(&with, &[backlash]), vec![backlash]);
        assert_eq!(with_rounding(&with, &[]), Vec::<Effect>::new());
    }

    #[test]
    fn the_choice_parses_and_prints_back() {
        assert_eq!(
            "auto".parse::<EffectsChoice>().unwrap(),
            EffectsChoice::Auto
        );
        assert_eq!(
            "none".parse::<EffectsChoice>().unwrap(),
            EffectsChoice::None
        );
        let g: EffectsChoice = "backlash_y, setup_error".parse().unwrap();
        assert_eq!(g.to_string(), "backlash_y,setup_error");
        assert_eq!(
            "backlash_q"
                .parse::<EffectsChoice>()
                .unwrap_err()
                .to_string(),
            "unknown effect id `backlash_q` (`testpiece machine` lists the ids)"
        );
        assert_eq!(
            "c_index,c_index"
                .parse::<EffectsChoice>()
                .unwrap_err()
                .to_string(),
            "candidate `c_index` appears twice"
        );
    }
}
