//! One physics part through the shipped analysis, and how its answer compares with the truth.
//!
//! A part measured once goes through [`crate::analysis::fit_points`], the function the CLI and
//! the page run once a file's points are matched (σ estimated, or the CMM's σ given when the run
//! says so: a CMM figure, never the part's scatter). A part measured several times goes through
//! what `testpiece diagnose --repeat` runs: its files written in the canonical format
//! ([`crate::cmm::write::canonical_csv`]) and read by [`crate::analysis::analyse_parts`] (the pure
//! error of the repeats, the analysis of their mean).
//!
//! Against the truth: the verdict ([`super::expected`]); the location errors of the final answer
//! and of the baseline within 2 std of the simulated ones ([`crate::validate::answer_error`]); the
//! final answer's std over the std of the **true model's fit** (the location errors fitted with
//! the part's own effect as a known shape, its noise-free deviation less that of the location
//! errors alone, one more column of unknown amplitude; σ the true one): an honest std near 1, an
//! inflated one above it.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::analysis::{analyse_parts, fit_points, AnalysisOptions, Diagnosis};
use crate::cmm::write::{canonical_csv, Precision};
use crate::gap::verdict::VerdictId;
use crate::identify::solve::{hstack, rms, Factor};
use crate::identify::{Design, Identification};
use crate::parameter::Effect;
use crate::validate::parameter_error::{answer_error, AnswerError};
use crate::validate::physics::GeneratedPart;
use crate::validate::{ValidateError, ValidationModel};

use super::expected::{Catalogue, Expected};
use super::shape_check::ShapeCheck;

/// What the analysis said of a part.
#[derive(Debug, Clone)]
pub struct Analysed {
    pub verdict: VerdictId,
    /// The named effects (the verdict's, and the second of a pair).
    pub named: Vec<Effect>,
    /// The effects the verdict lists as equivalent to them.
    pub equivalent: Vec<Effect>,
    /// σ the diagnosis used (mm).
    pub sigma_used: f64,
    /// Points named outliers and left out.
    pub outliers: usize,
    pub baseline: Identification,
    pub answer: Identification,
    /// The named family's fitted shape against the physics ([`super::shape_check`]).
    pub shape: Option<ShapeCheck>,
}

/// The judged case.
#[derive(Debug, Clone, Serialize)]
pub struct Judged {
    pub expected: Expected,
    pub verdict: VerdictId,
    pub named: Vec<Effect>,
    pub right: bool,
    pub sigma_used: f64,
    pub outliers: usize,
    pub baseline_error: AnswerError,
    pub final_error: AnswerError,
    /// Per location error, the final std over the true model's std (NaN without a std).
    pub std_ratio: Vec<f64>,
    /// The named family's fitted shape against the physics.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shape: Option<ShapeCheck>,
}

/// The model a run scores against: the part, its points, the baseline design and candidates.
pub struct Scorer<'a> {
    pub model: &'a ValidationModel,
    pub location: Design,
    base: Factor,
    near: Box<dyn Fn(Effect, Effect) -> bool + 'a>,
    ids: Vec<String>,
    /// The settings prepared once for every repeated part (as the CLI holds them).
    session: crate::analysis::Session,
}

impl<'a> Scorer<'a> {
    pub fn new(model: &'a ValidationModel) -> Result<Self, ValidateError> {
        Ok(Self {
            location: model.location_design()?,
            base: Factor::new(&model.baseline.matrix, None),
            near: Box::new(model.near_equivalence()),
            ids: model.measured.iter().map(|p| p.id.to_string()).collect(),
            session: crate::analysis::Session::of(model.prepared.clone()),
            model,
        })
    }

    /// RMS (mm) of what the location errors cannot absorb of `d` (one value per point).
    pub fn visible(&self, d: &[f64]) -> f64 {
        rms(self
            .base
            .unabsorbed_vec(&DVector::from_column_slice(d))
            .as_slice())
    }

    /// The part through the shipped analysis (module docs); `cmm_sigma`: give the CMM's σ.
    pub fn analyse(
        &self,
        case: usize,
        part: &GeneratedPart,
        cmm_sigma: bool,
    ) -> Result<Analysed, ValidateError> {
        let m = self.model;
        let (diagnosis, outliers, baseline, answer) = if part.measurements.len() > 1 {
            let texts: Vec<String> = part
                .measurements
                .iter()
                .map(|y| {
                    canonical_csv(
                        m.measured.iter().zip(y.iter().copied()),
                        Precision::Shortest,
                        None,
                    )
                })
                .collect();
            let names: Vec<String> = (1..=texts.len())
                .map(|k| format!("repeat{k}.csv"))
                .collect();
            let files: Vec<(&[u8], &str)> = texts
                .iter()
                .zip(&names)
                .map(|(t, n)| (t.as_bytes(), n.as_str()))
                .collect();
            let (a, _) = analyse_parts(&self.session, &files, &m.settings)
                .map_err(|source| ValidateError::Analysis { case, source })?;
            let outliers = count_outliers(&a.outliers);
            (
                a.diagnosis,
                outliers,
                a.baseline.identification,
                a.identification,
            )
        } else {
            let settings = AnalysisOptions {
                noise_sigma: cmm_sigma.then_some(part.noise.cmm_sigma),
                ..m.settings.clone()
            };
            let fit = fit_points(
                &m.prepared,
                &m.at,
                &part.measurements[0],
                &self.ids,
                &settings,
            )
            .map_err(|source| ValidateError::Analysis { case, source })?;
            let outliers = count_outliers(&fit.outliers);
            (
                fit.diagnosis,
                outliers,
                fit.baseline.identification,
                fit.identification,
            )
        };
        let report = match &diagnosis {
            Diagnosis::Made { report, .. } => report,
            Diagnosis::NotMade { reason } => {
                return Err(ValidateError::NotDiagnosed {
                    case,
                    reason: reason.clone(),
                })
            }
        };
        let v = &report.verdict;
        let mut equivalent = v.finding.equivalent().to_vec();
        if let Some(w) = v.finding.with() {
            equivalent.extend(w.equivalent.iter().copied());
        }
        Ok(Analysed {
            shape: super::shape_check::check(&part.physics, report),
            verdict: v.id(),
            named: v.finding.effects(),
            equivalent,
            sigma_used: v.sigma,
            outliers,
            baseline,
            answer,
        })
    }

    /// The analysis of `part` judged against its truth: `catalogue`, `ratio` (visible structure
    /// over the limit), `limit` (mm).
    pub fn judge(
        &self,
        part: &GeneratedPart,
        catalogue: &Catalogue,
        ratio: f64,
        limit: f64,
        a: &Analysed,
    ) -> Judged {
        let expected = Expected::of(catalogue, ratio);
        let effect: Vec<f64> = part
            .noise_free
            .iter()
            .zip(&part.location_only)
            .map(|(a, b)| a - b)
            .collect();
        let absorbed = || !a.named.is_empty() && self.left_by(&a.named, &effect) < limit;
        let right = match &expected {
            Expected::None => a.verdict == VerdictId::Noise,
            Expected::Unexplained => a.verdict == VerdictId::Unexplained || absorbed(),
            Expected::Named(id) => {
                let also: &[_] = match catalogue {
                    Catalogue::In { also, .. } => also,
                    _ => &[],
                };
                let wanted: Vec<Effect> = std::iter::once(id)
                    .chain(also)
                    .filter_map(|c| c.effect())
                    .collect();
                wanted.iter().any(|w| {
                    a.named.contains(w)
                        || a.equivalent.contains(w)
                        || a.named.iter().any(|n| (self.near)(*n, *w))
                }) || absorbed()
            }
        };
        let params = self.location.parameters();
        let xi = DVector::from_column_slice(&part.xi);
        let true_std = self.true_model_std(&effect, part.sigma);
        let std_ratio = params
            .iter()
            .zip(&true_std)
            .map(|(p, t)| {
                a.answer
                    .parameters
                    .get(&p.name())
                    .and_then(|e| e.std)
                    .map_or(f64::NAN, |s| s / t)
            })
            .collect();
        Judged {
            expected,
            verdict: a.verdict,
            named: a.named.clone(),
            right,
            sigma_used: a.sigma_used,
            outliers: a.outliers,
            baseline_error: answer_error(params, &xi, &a.baseline),
            final_error: answer_error(params, &xi, &a.answer),
            std_ratio,
            shape: a.shape,
        }
    }

    /// RMS (mm) of what is left of `shape` once the location errors and the signatures of
    /// `effects` are fitted to it.
    fn left_by(&self, effects: &[Effect], shape: &[f64]) -> f64 {
        let mut x = self.model.baseline.matrix.clone();
        for e in effects {
            if let Some(c) = self.model.candidates.iter().find(|c| c.effect == *e) {
                x = hstack(&x, &c.signature.matrix);
            }
        }
        rms(Factor::new(&x, None)
            .unabsorbed_vec(&DVector::from_column_slice(shape))
            .as_slice())
    }

    /// The std of each location error (rad, mm) in the true model's fit: the location errors
    /// and the part's effect as one more column, σ the true one.
    fn true_model_std(&self, effect: &[f64], sigma: f64) -> Vec<f64> {
        let a = &self.model.baseline.matrix;
        let x = if effect.iter().any(|v| v.abs() > 1e-12) {
            hstack(a, &DMatrix::from_column_slice(effect.len(), 1, effect))
        } else {
            a.clone()
        };
        let f = Factor::new(&x, None);
        (0..a.ncols())
            .map(|j| sigma * f.cov[(j, j)].sqrt())
            .collect()
    }
}

fn count_outliers(o: &crate::analysis::Outliers) -> usize {
    match (&o.test, o.excluded) {
        (Some(t), true) => t.points.len(),
        _ => 0,
    }
}
