//! The diagnosis of a part on the chosen machine: its part model, the outlier test and the
//! sim-to-real gap diagnosis (with every point, then without the outliers).

use std::borrow::Cow;

use serde::Serialize;

use crate::effects::builtin::PartModel;
use crate::effects::prepared::Prepared;
use crate::effects::{GapError, GapInput};
use crate::gap::shape::{f_quantile, SHAPE_CONFIDENCE};
use crate::gap::verdict::VerdictId;
use crate::gap::{
    diagnose, diagnose_on, diagnose_with, ground, DiagnoseOptions, DiagnosisReport, Ground,
};
use crate::machine::AxisName;
use crate::measurement::outliers::{find_outliers_with_fit_on, without_rows, OutlierTest};
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
    /// The part model (points, candidates' signatures), when it could be built: the points'
    /// model, or that model with a named backlash's take-up ([`take_up_rounds`]).
    pub(super) model: Option<Cow<'a, PartModel>>,
    /// Effects the machine does not have ([`Effect::left_out`]), and why.
    pub(super) unavailable: Vec<(Effect, String)>,
    /// The outlier test (when the model could be built) and the rows left out.
    pub(super) outliers: Option<OutlierTest>,
    pub(super) excluded: Vec<usize>,
    /// The verdict on every point, when outliers were left out.
    pub(super) verdict_all_points: Option<VerdictId>,
}

/// Diagnoses with a named backlash's take-up at most this many times beyond the first diagnosis.
pub const TAKE_UP_ROUNDS: usize = 3;
/// The lost motion found and the one the take-up was modelled with agree to this fraction: the
/// rounds stop.
pub const TAKE_UP_AGREEMENT: f64 = 0.05;

/// The outlier test and the diagnosis on one part model (with every point, then without the
/// outliers unless kept).
struct Run {
    report: DiagnosisReport,
    /// The verdict's in-sample residual sum of squares with every point (mm²), and the σ of that
    /// diagnosis (mm).
    rss_all: f64,
    sigma_all: f64,
    verdict_all_points: Option<VerdictId>,
}

/// What every diagnosis of one part's deviations shares whatever its candidates' families:
/// the outlier test (it reads the candidates' signatures, not their families), the rows it
/// leaves out, and the diagnosis's [`Ground`] on every point when it leaves none out. A named
/// backlash's take-up changes its family only, so its rounds are diagnosed on these (they had
/// been computed again each round: ~0.8 s of a 20,000-point C-backlash scan's 2.5 s round). A
/// part with rows left out is diagnosed twice a round (with every point, then without them), and
/// each ground is made for its diagnosis and freed after it, as before: the two grounds at once
/// would be ~0.2 GB more at the peak of a 200,000-point scan.
struct Shared {
    outliers: OutlierTest,
    excluded: Vec<usize>,
    /// The ground on every point (the first made with the outlier test's fit of `[A | smooth
    /// basis]`), kept from round to round when no row is left out.
    all: Option<Ground>,
}

fn diagnose_options(opts: &AnalysisOptions) -> DiagnoseOptions {
    DiagnoseOptions {
        threads: opts.threads,
        ..DiagnoseOptions::default()
    }
}

fn shared(m: &PartModel, deviations: &[f64], opts: &AnalysisOptions) -> Result<Shared, GapError> {
    let input = input_of(m, deviations, opts.noise_sigma);
    // the test's plain fit of [A | smooth basis] on every row is the diagnosis's
    let (test, smooth) = find_outliers_with_fit_on(&input, opts.threads);
    let drop = if opts.keep_outliers {
        Vec::new()
    } else {
        test.indices()
    };
    Ok(Shared {
        outliers: test,
        excluded: drop,
        all: Some(ground(&input, diagnose_options(opts), smooth)?),
    })
}

fn run(
    m: &PartModel,
    deviations: &[f64],
    opts: &AnalysisOptions,
    shared: &mut Shared,
) -> Result<Run, GapError> {
    let input = input_of(m, deviations, opts.noise_sigma);
    let dopts = diagnose_options(opts);
    let g = match shared.all.take() {
        Some(g) => g,
        None => ground(&input, dopts, None)?,
    };
    let all = diagnose_on(&input, dopts, &g)?;
    let rss_all = all.verdict.rms_after.powi(2) * deviations.len() as f64;
    let sigma_all = all.structure.noise.used;
    let (report, verdict_all_points) = if shared.excluded.is_empty() {
        shared.all = Some(g);
        (all, None)
    } else {
        // (freed before the diagnosis without the rows, which makes its own)
        drop(g);
        let v = all.verdict.id();
        let kept = without_rows(&input, &shared.excluded);
        (diagnose_with(&kept, dopts)?, Some(v))
    };
    Ok(Run {
        report,
        rss_all,
        sigma_all,
        verdict_all_points,
    })
}

/// The lost motion of each backlash the verdict names (alone or in a pair), from its fit
/// (`b`, mm or rad; a pair's member as `backlash_<axis>.b`).
fn named_backlash(report: &DiagnosisReport) -> Vec<(AxisName, f64)> {
    let finding = &report.verdict.finding;
    let named = finding.effects();
    let with = finding.with().map(|m| m.effect);
    let fit = report
        .candidates
        .iter()
        .find(|f| named.first() == Some(&f.effect) && f.with == with);
    let Some(fit) = fit else {
        return Vec::new();
    };
    named
        .iter()
        .filter_map(|e| match e {
            Effect::Backlash(axis) => {
                let key = if with.is_some() {
                    format!("{}.b", e.id())
                } else {
                    "b".to_string()
                };
                fit.parameters.get(&key).map(|p| (*axis, p.value))
            }
            _ => None,
        })
        .collect()
}

/// The diagnosis of a backlash corrected for the play's take-up ([`crate::sensitivity::take_up`]:
/// its shape depends on the lost motion `b` itself): while the verdict names a backlash whose
/// fitted `b` differs by more than [`TAKE_UP_AGREEMENT`] from the `b` its columns were built
/// with (none at first), the part model is rebuilt with the take-up of the fitted `b` and the
/// part diagnosed again, at most [`TAKE_UP_ROUNDS`] times (a fixed point of `b`). A round is kept
/// only when its verdict names the same effects as the round before, with a residual on every
/// point not significantly larger; otherwise the rounds stop at the round before. A part whose
/// verdict names no backlash is diagnosed once, on the points' model as it is.
fn take_up_rounds<'a>(
    prepared: &Prepared,
    base: &'a PartModel,
    deviations: &[f64],
    opts: &AnalysisOptions,
) -> Result<(Run, Shared, Cow<'a, PartModel>), GapError> {
    let mut model = Cow::Borrowed(base);
    let mut shared = shared(base, deviations, opts)?;
    let mut result = run(base, deviations, opts, &mut shared)?;
    let mut used: Vec<(AxisName, f64)> = Vec::new();
    for _ in 0..TAKE_UP_ROUNDS {
        let found: Vec<(AxisName, f64)> = named_backlash(&result.report)
            .into_iter()
            .map(|(a, b)| (a, b.max(0.0)))
            .collect();
        let agrees = found.iter().all(|(a, b)| {
            let before = used.iter().find(|(x, _)| x == a).map_or(0.0, |u| u.1);
            (b - before).abs() <= TAKE_UP_AGREEMENT * b.abs().max(before.abs())
        });
        if found.is_empty() || agrees {
            break;
        }
        let next = base.with_take_up(prepared.path(), &found)?;
        let again = run(&next, deviations, opts, &mut shared)?;
        // the take-up refines the named backlash's shape, it does not choose another effect:
        // a round whose part names other effects is dropped (a part made without a take-up, e.g.
        // by the catalogue's signatures, keeps the switched shape). Their residuals do not decide:
        // the take-up and a longer lag fit a part about as closely (the rounds' in-sample RMS
        // differ by ±0.2 % on the physics generator's backlash parts), and the physics of a
        // dead band says the play is taken up.
        if again.report.verdict.finding.effects() != result.report.verdict.finding.effects() {
            break;
        }
        // ... nor a round whose residual on every point the data find significantly larger
        // (equal parameter counts: (ΔRSS/σ²) against F₀.₉₅(1, n), the shape's own bound): a play
        // switched at the reversal, as the catalogue's signatures make it, leaves the points
        // after each reversal far from a take-up ramp
        let n = deviations.len() as f64;
        let s2 = result.sigma_all.max(f64::MIN_POSITIVE).powi(2);
        if (again.rss_all - result.rss_all) / s2 > f_quantile(SHAPE_CONFIDENCE, n.max(1.0)) {
            break;
        }
        result = again;
        model = Cow::Owned(next);
        used = found;
    }
    Ok((result, shared, model))
}

pub(super) fn diagnose_modelled<'a>(
    prepared: &Prepared,
    at: &'a PointsModel,
    deviations: &[f64],
    opts: &AnalysisOptions,
) -> Modelled<'a> {
    let made = at
        .part_model()
        .and_then(|m| take_up_rounds(prepared, m, deviations, opts));
    let mut unavailable = Effect::left_out(&opts.machine.chain(opts.l0));
    unavailable.extend(prepared.location_equivalents().iter().cloned());
    match made {
        Ok((r, shared, model)) => Modelled {
            diagnosis: Diagnosis::Made {
                machine: opts.machine,
                report: Box::new(r.report),
            },
            model: Some(model),
            unavailable,
            outliers: Some(shared.outliers),
            excluded: shared.excluded,
            verdict_all_points: r.verdict_all_points,
        },
        Err(e) => Modelled {
            diagnosis: Diagnosis::NotMade { reason: e },
            model: None,
            unavailable,
            outliers: None,
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
        points: std::borrow::Cow::Borrowed(&m.points),
        baseline: std::borrow::Cow::Borrowed(&m.baseline),
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
