//! The diagnosis of a part on the chosen machine: its part model, the outlier test and the
//! sim-to-real gap diagnosis (with every point, then without the outliers).

use serde::Serialize;

use crate::effects::builtin::PartModel;
use crate::effects::prepared::Prepared;
use crate::effects::{GapError, GapInput};
use crate::gap::verdict::VerdictId;
use crate::gap::{diagnose, diagnose_with_smooth, DiagnoseOptions, DiagnosisReport};
use crate::measurement::outliers::{find_outliers_with_fit, without_rows, OutlierTest};
use crate::parameter::Effect;
use crate::settings::MachineChoice;

use super::error::AnalysisError;
use super::options::AnalysisOptions;
use super::session::PointsModel;

/// The gap diagnosis (effects.md) of deviations at the points of `at`, on the settings its model
/// was built on, with every point (no outlier test).
pub fn diagnose_points(
    at: &PointsModel,
    deviations: &[f64],
    noise_sigma: Option<f64>,
) -> Result<DiagnosisReport, GapError> {
    diagnose_model(at.part_model()?, deviations, noise_sigma)
}

/// The gap diagnosis of an analysis, or why it could not be made (JSON: `status` = `made` or
/// `not_made`).
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Diagnosis {
    Made {
        /// The machine whose errors and axes the diagnosis used (the identification's).
        machine: MachineChoice,
        report: Box<DiagnosisReport>,
    },
    NotMade {
        /// The diagnosis stage's error (serialised as its message).
        #[serde(serialize_with = "as_message")]
        reason: GapError,
    },
}

/// An error as its message.
fn as_message<S: serde::Serializer>(e: &GapError, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(e)
}

impl Diagnosis {
    /// The report, when the diagnosis was made.
    pub fn report(&self) -> Option<&DiagnosisReport> {
        match self {
            Diagnosis::Made { report, .. } => Some(report),
            Diagnosis::NotMade { .. } => None,
        }
    }
    /// The report, or the reason it could not be made.
    pub fn into_report(self) -> Result<DiagnosisReport, AnalysisError> {
        match self {
            Diagnosis::Made { report, .. } => Ok(*report),
            Diagnosis::NotMade { reason } => Err(AnalysisError::NotDiagnosed { reason }),
        }
    }
}

/// The gap diagnosis on the machine the analysis identifies: its own location errors as the
/// baseline, its own candidates ([`Effect::on_chain`]) with their signatures derived from its
/// chain, its own axes for backlash, scale and reversals (`prepared`: its settings, `at`: the
/// points' model on them).
pub fn diagnose_on_machine(
    prepared: &Prepared,
    at: &PointsModel,
    deviations: &[f64],
    opts: &AnalysisOptions,
) -> Diagnosis {
    diagnose_modelled(prepared, at, deviations, opts).diagnosis
}

/// A diagnosis with the part model it used, for the final identification.
pub(super) struct Modelled<'a> {
    pub(super) diagnosis: Diagnosis,
    /// The part model (points, candidates' signatures), when it could be built.
    pub(super) model: Option<&'a PartModel>,
    /// Effects the machine does not have ([`Effect::left_out`]), and why.
    pub(super) unavailable: Vec<(Effect, String)>,
    /// The outlier test (when the model could be built) and the rows left out.
    pub(super) outliers: Option<OutlierTest>,
    pub(super) excluded: Vec<usize>,
    /// The verdict on every point, when outliers were left out.
    pub(super) verdict_all_points: Option<VerdictId>,
}

pub(super) fn diagnose_modelled<'a>(
    prepared: &Prepared,
    at: &'a PointsModel,
    deviations: &[f64],
    opts: &AnalysisOptions,
) -> Modelled<'a> {
    let mut outliers = None;
    let mut excluded = Vec::new();
    let mut verdict_all_points = None;
    // The outliers of the part (named, and left out unless kept), then the diagnosis.
    let mut run = |m: &PartModel| -> Result<DiagnosisReport, GapError> {
        let input = input_of(m, deviations, opts.noise_sigma);
        // the test's plain fit of [A | smooth basis] on every row is the diagnosis's
        let (test, smooth) = find_outliers_with_fit(&input);
        let drop = if opts.keep_outliers {
            Vec::new()
        } else {
            test.indices()
        };
        outliers = Some(test);
        let all = diagnose_with_smooth(&input, DiagnoseOptions::default(), smooth)?;
        let report = if drop.is_empty() {
            all
        } else {
            verdict_all_points = Some(all.verdict.id());
            diagnose(&without_rows(&input, &drop))?
        };
        excluded = drop;
        Ok(report)
    };
    let made = at
        .part_model()
        .and_then(|m| run(m).map(|report| (report, m)));
    let mut unavailable = Effect::left_out(&opts.machine.chain(opts.l0));
    unavailable.extend(prepared.location_equivalents().iter().cloned());
    match made {
        Ok((report, model)) => Modelled {
            diagnosis: Diagnosis::Made {
                machine: opts.machine,
                report: Box::new(report),
            },
            model: Some(model),
            unavailable,
            outliers,
            excluded,
            verdict_all_points,
        },
        Err(e) => Modelled {
            diagnosis: Diagnosis::NotMade { reason: e },
            model: None,
            unavailable,
            outliers,
            excluded: Vec::new(),
            verdict_all_points: None,
        },
    }
}

/// The diagnosis's input for a part model and deviations.
pub(super) fn input_of<'a>(
    m: &'a PartModel,
    deviations: &[f64],
    noise_sigma: Option<f64>,
) -> GapInput<'a> {
    GapInput {
        deviations: deviations.to_vec(),
        points: m.points.clone(),
        baseline: m.baseline.clone(),
        candidates: std::borrow::Cow::Borrowed(&m.candidates),
        noise_sigma,
        reversals: m.reversals.clone(),
    }
}

pub(super) fn diagnose_model(
    m: &PartModel,
    deviations: &[f64],
    noise_sigma: Option<f64>,
) -> Result<DiagnosisReport, GapError> {
    diagnose(&input_of(m, deviations, noise_sigma))
}
